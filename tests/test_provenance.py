"""Provenance beside every table: the config hash (order-free, value-sensitive), the git commit (or "not a git
checkout"), the voxpose, Python and package versions."""

import json
import platform
import subprocess
from importlib import metadata

import pytest

from voxpose import __version__
from voxpose.provenance import NOT_GIT, config_hash, git_commit, meta_path, write_meta


def test_config_hash_ignores_key_order_and_sees_every_value():
    a = {"features": {"n_components": 16, "q": 3}, "seed": 0}
    b = {"seed": 0, "features": {"q": 3, "n_components": 16}}
    assert config_hash(a) == config_hash(b)
    assert config_hash(a) != config_hash({"seed": 0, "features": {"q": 3, "n_components": 17}})
    assert config_hash(a).startswith("sha256:") and len(config_hash(a)) == len("sha256:") + 64


def _git(repo, *args):
    subprocess.run(["git", "-C", str(repo), "-c", "user.name=t", "-c", "user.email=t@t", *args], check=True,
                   capture_output=True)  # fmt: skip


def test_git_commit_of_a_checkout_a_modified_one_and_none(tmp_path):
    assert git_commit(tmp_path) == NOT_GIT
    _git(tmp_path, "init", "-q", "-b", "main")
    (tmp_path / "f.txt").write_text("one")
    _git(tmp_path, "add", "f.txt")
    _git(tmp_path, "commit", "-q", "-m", "first")
    head = (tmp_path / ".git/refs/heads/main").read_text().strip()  # the commit, read without asking git
    assert len(head) == 40 and git_commit(tmp_path) == head
    (tmp_path / "untracked.txt").write_text("not part of the checkout")
    assert git_commit(tmp_path) == head
    (tmp_path / "f.txt").write_text("two")
    assert git_commit(tmp_path) == f"{head}+modified"


def test_meta_beside_the_table(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # not a git checkout
    table = tmp_path / "tables/table1.csv"
    table.parent.mkdir()
    write_meta(table, "sha256:abc")
    assert meta_path(table) == tmp_path / "tables/table1.meta.json"
    meta = json.loads(meta_path(table).read_text())
    assert meta["config_hash"] == "sha256:abc"
    assert meta["git_commit"] == NOT_GIT
    assert meta["voxpose"] == __version__
    assert meta["python"] == platform.python_version()
    for name in ("numpy", "scipy", "h5py", "pandas", "matplotlib", "snakemake"):
        assert meta["packages"][name] == metadata.version(name)


@pytest.mark.parametrize("config_hash_, shown", [("sha256:0123", "sha256:0123"), (None, "none (run outside")])
def test_a_table_command_writes_its_provenance(tmp_path, config_hash_, shown):
    from tests.helpers import run_voxpose

    runs = []
    for label, value, error in (("n_r", 2, 7.5), ("n_r", 3, 7.0)):
        summary = tmp_path / f"{label}{value}.json"
        summary.write_text(json.dumps({"methods": {"mvrvm": {"full_body": error}, "mean_pose": {"full_body": 10.0}},
                                       "n_relevance": 5, "train_frames": 20, "test_frames": 10}))
        runs.append([label, value, str(summary)])
    args = ["figure4", "--runs", json.dumps(runs), "--png", tmp_path / "f.png", "--pdf", tmp_path / "f.pdf",
            "--csv", tmp_path / "f.csv"]  # fmt: skip
    if config_hash_:
        args += ["--config-hash", config_hash_]
    proc = run_voxpose(*args)
    assert proc.returncode == 0, proc.stderr
    assert json.loads((tmp_path / "f.meta.json").read_text())["config_hash"].startswith(shown)
