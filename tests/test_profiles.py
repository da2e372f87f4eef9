"""The shipped profiles and their README: the SLURM profile needs no accounting database, every cluster rule sizes
its resources from its input, and profiles/README.md states the workflow's facts (which rules run where, how many
per-motion jobs go into how many SLURM jobs) as the workflow has them."""

import re
import subprocess
import sys

import pytest
import yaml

from tests.helpers import ROOT

README = (ROOT / "profiles/README.md").read_text()


def _rules() -> dict:
    """Rule name -> its text, from workflow/rules/*.smk."""
    out = {}
    for path in (ROOT / "workflow/rules").glob("*.smk"):
        for block in re.split(r"(?m)^(?=rule \w+:)", path.read_text())[1:]:
            out[re.match(r"rule (\w+):", block)[1]] = block
    return out


def _listed(section: str) -> set:
    return set(re.findall(r"`(\w+)`", section))


def test_the_slurm_profile_asks_squeue_for_job_states():
    # sacct, the plugin's default, fails without an accounting database and the run hangs (issue 21)
    profile = yaml.safe_load((ROOT / "profiles/slurm/config.yaml").read_text())
    assert profile["slurm-status-command"] == "squeue"


@pytest.mark.parametrize("profile", ["default", "slurm"])
def test_the_scheduler_reevaluates_every_few_seconds_not_every_second(profile):
    """Every finished job adds a re-evaluation of all ready jobs per max-jobs-per-timespan timespan (Snakemake 9;
    benchmarks/snakemake_cpu.py): at Snakemake's 1 s default its own process took 13 % of the quick run's wall
    time. The profiles keep the timespan at 5 s, so a run waits at most that for its last timer."""
    setting = yaml.safe_load((ROOT / f"profiles/{profile}/config.yaml").read_text())["max-jobs-per-timespan"]
    count, span = re.fullmatch(r"(\d+)/(\d+)s", setting).groups()
    assert int(span) == 5 and int(count) >= 100


def test_the_readme_names_every_local_and_every_per_motion_rule():
    rules = _rules()
    local = {name for name, text in rules.items() if re.search(r"^\s+localrule: True", text, re.M)}
    grouped = {name for name, text in rules.items() if re.search(r'^\s+group: "per_motion"', text, re.M)}
    login = README.split("- **Login node**", 1)[1].split("- **SLURM jobs**", 1)[0]
    per_motion = README.split("- **SLURM jobs**", 1)[1].split("form the group", 1)[0]
    assert _listed(login) & set(rules) == local
    assert _listed(per_motion) & set(rules) == grouped


def test_every_cluster_rule_sizes_its_resources_from_its_input():
    for name, text in _rules().items():
        if "localrule: True" in text or "resources:" not in text:
            continue
        resources = text.split("resources:", 1)[1].split("shell:", 1)[0]
        for key in ("mem_mb", "runtime"):
            assert re.search(rf"{key}=by_(input|frames)\(", resources), f"rule {name}: {key} is not measured"


@pytest.mark.parametrize("configfile, jobs, batches", [("config/quick.yaml", 77, 2), ("config/config.yaml", 200, 4)])
def test_per_motion_jobs_and_their_slurm_batches_are_as_the_readme_says(configfile, jobs, batches):
    assert f"{jobs} per-motion jobs are {batches} SLURM jobs" in README or (
        f"default's {jobs} are {batches}" in README and configfile == "config/config.yaml")
    cmd = [sys.executable, "-m", "snakemake", "-n", "--forceall", "--group-components", "per_motion=5",
           "--configfile", configfile]  # fmt: skip
    out = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, check=True).stdout
    stats = dict(re.findall(r"^(\w+)\s+(\d+)\s*$", out.split("Job stats:", 1)[1].split("\n\n", 1)[0], re.M))
    grouped = [name for name, text in _rules().items() if 'group: "per_motion"' in text]
    assert sum(int(stats.get(name, 0)) for name in grouped) == jobs
    assert out.count("Group job per_motion") == batches
