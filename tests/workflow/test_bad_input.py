"""Bad input through the workflow. A config/config.yaml that is not valid YAML is one line naming the file and
line. Malformed BVH files in ``bvh_dir`` (tests/io/bvh_corpus.py) through the workflow: a header error is the
command's one line, once, before any job, in a dry run and a run alike (it was an InputFunctionException
traceback blaming whichever rule Snakemake sized first); an error in the frame lines fails that motion's job
with the command's line; the well-formed variants are loaded."""

import pytest

from tests.helpers import copy_workflow, snakemake
from tests.io.bvh_corpus import corpus, write_corpus
from voxpose.errors import VoxposeError
from voxpose.io.bvh import read_bvh

pytestmark = pytest.mark.workflow  # slow: deselect with -m "not workflow"

CASES = {c.name: c for c in corpus()}


@pytest.fixture(scope="module")
def workdir(tmp_path_factory):
    return copy_workflow(tmp_path_factory.mktemp("bad_input"))


def _cli_message(path) -> str:
    with pytest.raises(VoxposeError) as err:
        read_bvh(path)
    return f"voxpose: error: {err.value}"


def _no_traceback(proc):
    text = proc.stdout + proc.stderr
    assert "Traceback" not in text and "InputFunctionException" not in text, text[-3000:]


@pytest.mark.parametrize(("name", "dry"), [("channel_unknown", True), ("channel_unknown", False),
                                           ("utf16", True), ("empty", True)])  # fmt: skip
def test_a_header_error_is_the_commands_line_once_before_any_job(workdir, tmp_path, name, dry):
    path = write_corpus(tmp_path / "bvh", [CASES[name]])[name]
    proc = snakemake(workdir, *(["-n"] if dry else []), "--config", f"bvh_dir={path.parent}", check=False)
    _no_traceback(proc)
    assert proc.returncode == 2
    errors = [line for line in (proc.stdout + proc.stderr).splitlines() if "error" in line.lower()]
    assert errors == [_cli_message(path)]
    assert "rule " not in proc.stdout + proc.stderr  # no rule is blamed
    assert not (workdir / "results").exists()


def test_frame_errors_fail_their_motion_jobs_and_good_files_load(workdir, tmp_path):
    chosen = [c for c in corpus() if c.part != "header"]
    paths = write_corpus(tmp_path / "bvh", chosen)
    proc = snakemake(workdir, "--keep-going", "--config", f"bvh_dir={tmp_path / 'bvh'}", check=False)
    _no_traceback(proc)
    assert proc.returncode != 0
    # each job writes its line whole, newline included, but Snakemake writes some of its own lines in two parts
    # (the text, then the newline): a job that fails in between lands on the end of one of those. Seen under load
    # as "...returned non-zero exit status 2.voxpose: error: ...". So the count is of the message, not of lines.
    text = proc.stdout + proc.stderr
    for case in chosen:
        made = (workdir / "results" / "motions" / f"walk_{case.name}.h5").exists()
        if case.part:
            assert text.count(_cli_message(paths[case.name]) + "\n") == 1, case.name
            assert not made
        else:
            assert made, case.name


def test_broken_yaml_in_the_workflows_config_names_file_and_line(tmp_path):
    work = copy_workflow(tmp_path)
    config = work / "config" / "config.yaml"
    lines = config.read_text().splitlines()
    line = next(i for i, text in enumerate(lines) if text.strip().startswith("tol:")) + 1
    lines[line - 1] = lines[line - 1].replace("tol:", "tol: [1.0", 1)
    config.write_text("\n".join(lines) + "\n")
    proc = snakemake(work, "-n", check=False)
    _no_traceback(proc)
    assert proc.returncode == 2
    last = proc.stderr.strip().splitlines()[-1]
    assert last.startswith("voxpose: error: config/config.yaml:") and f"(from line {line})" in last, last
