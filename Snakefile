# voxpose: regression-based human motion capture from voxel data (Sun et al., BMVC 2006).
# One command reproduces the paper's artifacts:  snakemake --cores all   (see README.md)

from snakemake.utils import min_version

min_version("9.0")


include: "workflow/rules/config_file.smk"

configfile: "config/config.yaml"


include: "workflow/rules/common.smk"
include: "workflow/rules/motions.smk"
include: "workflow/rules/voxels.smk"
include: "workflow/rules/descriptors.smk"
include: "workflow/rules/features.smk"
include: "workflow/rules/regression.smk"
include: "workflow/rules/evaluation.smk"
include: "workflow/rules/figures.smk"
include: "workflow/rules/models.smk"
include: "workflow/rules/claims.smk"


report: "workflow/report/workflow.rst"


rule all:
    input:
        final_targets(),
    default_target: True
