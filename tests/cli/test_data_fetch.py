"""``voxpose data-fetch``: a failure is one line and exit 2; --list, --manifest and the mirror variable work."""

import socket

from tests.helpers import one_line_error, run_voxpose
from tests.io.data_mirror import COMMIT, FILES, build_mirror, write_manifest


def _closed_port() -> int:
    """A local port nothing listens on: connecting to it is refused at once, with no network needed."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_fetch_through_the_mirror_variable(tmp_path, monkeypatch):
    base, manifest = build_mirror(tmp_path)
    path = write_manifest(tmp_path / "sets.json", manifest)
    monkeypatch.setenv("VOXPOSE_DATA_BASE_URL", base)
    proc = run_voxpose("data-fetch", "demo", tmp_path / "out", "--manifest", path)
    assert proc.returncode == 0, proc.stderr
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == sorted(FILES)


def test_a_refused_connection_is_one_line_naming_the_url(tmp_path):
    _, manifest = build_mirror(tmp_path)
    path = write_manifest(tmp_path / "sets.json", manifest)
    base = f"http://127.0.0.1:{_closed_port()}"
    proc = run_voxpose("data-fetch", "demo", tmp_path / "out", "--manifest", path, "--base-url", base)
    one_line_error(proc, f"cannot download {base}/someone/motions/{COMMIT}/data/01/01_01.bvh: ", "refused")


def test_a_wrong_checksum_is_one_line_and_nothing_is_left(tmp_path):
    base, manifest = build_mirror(tmp_path, sha256={"walk_demo_01.bvh": "0" * 64})
    path = write_manifest(tmp_path / "sets.json", manifest)
    proc = run_voxpose("data-fetch", "demo", tmp_path / "out", "--manifest", path, "--base-url", base)
    one_line_error(proc, "walk_demo_01.bvh: checksum mismatch")
    assert list((tmp_path / "out").iterdir()) == []


def test_list_prints_each_set_with_its_file_count_and_size(tmp_path):
    _, manifest = build_mirror(tmp_path)
    proc = run_voxpose("data-fetch", "--list", "--manifest", write_manifest(tmp_path / "sets.json", manifest))
    assert proc.returncode == 0, proc.stderr
    size_mb = sum(len(content) for _, content in FILES.values()) / 1e6
    assert proc.stdout.split("\t")[:3] == ["demo", "2 files", f"{size_mb:.1f} MB"]


def test_the_shipped_sets_are_listed():
    proc = run_voxpose("data-fetch", "--list")
    assert proc.returncode == 0, proc.stderr
    rows = [line.split("\t")[:2] for line in proc.stdout.splitlines()]
    assert rows == [["bvh", "42 files"], ["bvh-library", "43 files"]]


def test_a_missing_folder_argument_is_one_line():
    one_line_error(run_voxpose("data-fetch", "bvh"), "needs a set and a folder")
