# voxpose: regression-based human motion capture from voxel data (Sun et al., BMVC 2006).
# One command reproduces the paper's artifacts:  snakemake --cores all   (see README.md)

from snakemake.utils import min_version

min_version("9.0")


include: "workflow/rules/config_file.smk"

configfile: "config/config.yaml"


# `snakemake --lint` asks each rule for a conda environment or a container; the rules marked `# lint: no
# conda/container` have none on purpose: every rule runs the `voxpose` command of the environment Snakemake runs in,
# installed from requirements.lock (exact versions with hashes, README), which a per-rule environment would duplicate
# and could let drift from the tested one. tests/test_lint.py checks that this is the only lint left.


include: "workflow/rules/common.smk"
include: "workflow/rules/motions.smk"
include: "workflow/rules/voxels.smk"
include: "workflow/rules/descriptors.smk"
include: "workflow/rules/features.smk"
include: "workflow/rules/regression.smk"
include: "workflow/rules/evaluation.smk"
include: "workflow/rules/figures.smk"
include: "workflow/rules/models.smk"
include: "workflow/rules/claims_common.smk"
include: "workflow/rules/claims.smk"
include: "workflow/rules/job_server.smk"


report: "workflow/report/workflow.rst"


rule all:
    input:
        final_targets(),
    default_target: True
