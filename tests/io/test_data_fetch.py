"""Fetching the real data sets: pinned checksums, atomic writes, skips on rerun, mirrors; the shipped manifest."""

import functools
import hashlib
import http.server
import re
import threading

import pytest

from tests.helpers import SHARED_BVH
from tests.io.data_mirror import COMMIT, FILES, GITHUB, build_mirror
from voxpose.errors import VoxposeError
from voxpose.io.data_fetch import fetch_set, load_manifest, mirrored, set_files


def _listing(folder):
    return sorted(p.name for p in folder.iterdir())


def test_every_file_arrives_under_the_name_the_config_expects(tmp_path):
    base, manifest = build_mirror(tmp_path)
    dest = tmp_path / "bvh"
    assert fetch_set(manifest, "demo", dest, base_url=base) == {"fetched": 2, "skipped": 0}
    assert _listing(dest) == sorted(FILES)  # renamed, and no temporary file left beside them
    for name, (_, content) in FILES.items():
        assert (dest / name).read_bytes() == content


def test_a_checksum_mismatch_is_refused_naming_the_file_and_leaves_nothing(tmp_path):
    base, manifest = build_mirror(tmp_path, sha256={"jog_demo_02.bvh": hashlib.sha256(b"other").hexdigest()})
    dest = tmp_path / "bvh"
    with pytest.raises(VoxposeError, match=r"jog_demo_02\.bvh: checksum mismatch") as err:
        fetch_set(manifest, "demo", dest, base_url=base)
    assert "\n" not in str(err.value)
    assert _listing(dest) == ["walk_demo_01.bvh"]  # the good file before it stays, verified


def test_an_unreachable_url_is_one_line_naming_it(tmp_path):
    _, manifest = build_mirror(tmp_path)
    base = (tmp_path / "no-such-mirror").as_uri()
    with pytest.raises(VoxposeError) as err:
        fetch_set(manifest, "demo", tmp_path / "bvh", base_url=base)
    url = f"{base}/someone/motions/{COMMIT}/data/01/01_01.bvh"
    assert str(err.value).startswith(f"cannot download {url}: ")
    assert "\n" not in str(err.value)
    assert not (tmp_path / "bvh").exists() or _listing(tmp_path / "bvh") == []


@pytest.fixture
def http_mirror(tmp_path):
    """The mirror served over HTTP on a local port (no network needed): the scheme real downloads use."""
    base, manifest = build_mirror(tmp_path)
    handler = functools.partial(http.server.SimpleHTTPRequestHandler, directory=tmp_path / "mirror")
    handler.log_message = lambda *args: None
    with http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler) as server:
        threading.Thread(target=server.serve_forever, daemon=True).start()
        yield f"http://127.0.0.1:{server.server_address[1]}", manifest
        server.shutdown()


def test_fetch_over_http_and_a_missing_file_is_named_with_its_status(http_mirror, tmp_path):
    base, manifest = http_mirror
    fetch_set(manifest, "demo", tmp_path / "bvh", base_url=base)
    assert (tmp_path / "bvh" / "jog_demo_02.bvh").read_bytes() == FILES["jog_demo_02.bvh"][1]
    manifest["sets"]["demo"][0]["url"] += ".gone"
    with pytest.raises(VoxposeError, match=r"^cannot download http://127\.0\.0\.1:\d+/\S+\.bvh\.gone: HTTP Error 404"):
        fetch_set(manifest, "demo", tmp_path / "other", base_url=base)


def test_a_rerun_skips_verified_files_and_replaces_a_corrupted_one(tmp_path):
    base, manifest = build_mirror(tmp_path)
    dest = tmp_path / "bvh"
    fetch_set(manifest, "demo", dest, base_url=base)
    (dest / "walk_demo_01.bvh").write_bytes(b"truncated")
    (tmp_path / "mirror" / "someone" / "motions" / COMMIT / FILES["jog_demo_02.bvh"][0]).unlink()
    # the jog file is no longer downloadable: the rerun succeeds only because it skips it
    assert fetch_set(manifest, "demo", dest, base_url=base) == {"fetched": 1, "skipped": 1}
    assert (dest / "walk_demo_01.bvh").read_bytes() == FILES["walk_demo_01.bvh"][1]


def test_a_base_url_replaces_only_the_github_prefix():
    url = f"{GITHUB}/o/r/{COMMIT}/a/b.bvh"
    assert mirrored(url, GITHUB, "file:///srv/mirror/") == f"file:///srv/mirror/o/r/{COMMIT}/a/b.bvh"
    assert mirrored(url, GITHUB, None) == url
    assert mirrored("https://example.org/x.bvh", GITHUB, "file:///m") == "https://example.org/x.bvh"


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"file": "../escape.bvh"}, "not a plain file name"),
        ({"sha256": "ABC"}, "sha256 is not 64"),
        ({"source": "elsewhere"}, "unknown source 'elsewhere'"),
    ],
)
def test_a_bad_manifest_entry_is_named(tmp_path, change, message):
    _, manifest = build_mirror(tmp_path)
    manifest["sets"]["demo"][1].update(change)
    with pytest.raises(VoxposeError, match=re.escape("sets.demo.1")) as err:
        set_files(manifest, "demo")
    assert message in str(err.value)


def test_an_unknown_set_names_the_known_ones(tmp_path):
    _, manifest = build_mirror(tmp_path)
    with pytest.raises(VoxposeError, match=r"unknown data set 'bvh' \(known: demo\)"):
        set_files(manifest, "bvh")


def test_the_shipped_manifest_pins_every_url_at_a_full_commit():
    manifest = load_manifest()
    assert set(manifest["sets"]) == {"bvh", "bvh-library"}
    for name in manifest["sets"]:
        for item in set_files(manifest, name):
            assert re.fullmatch(rf"{GITHUB}/[\w.-]+/[\w.-]+/[0-9a-f]{{40}}/\S+\.bvh", item.url), item.url


@pytest.mark.parametrize(("name", "folder"), [("bvh", SHARED_BVH), ("bvh-library", SHARED_BVH.parent / "bvh-library")])
def test_the_shipped_checksums_match_the_shared_copies(name, folder):
    if not folder.is_dir():
        pytest.skip(f"shared data not found at {folder}")
    items = set_files(load_manifest(), name)
    assert sorted(i.file for i in items) == sorted(p.name for p in folder.glob("*.bvh"))
    for item in items:
        data = (folder / item.file).read_bytes()
        assert (hashlib.sha256(data).hexdigest(), len(data)) == (item.sha256, item.bytes), item.file
