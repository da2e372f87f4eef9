"""A local stand-in for GitHub: files laid out as ``<owner>/<repo>/<commit>/<path>`` and a manifest naming them."""

import hashlib
import json

GITHUB = "https://raw.githubusercontent.com"
COMMIT = "0123456789abcdef0123456789abcdef01234567"

# name the config expects -> (path in the source repository, content); contents differ so a swap is caught
FILES = {
    "walk_demo_01.bvh": ("data/01/01_01.bvh", b"HIERARCHY\nROOT Hips\n walk one\n"),
    "jog_demo_02.bvh": ("data/dataset-1_run_normal_002.bvh", b"HIERARCHY\nROOT Hips\n a jog, two\n" * 3),
}


def build_mirror(root, files=FILES, sha256=None) -> tuple[str, dict]:
    """Write ``files`` under ``root/mirror`` and return the mirror's base URL and a one-set manifest ("demo").

    ``sha256`` overrides the pinned checksum of some files (file name -> hex digest), to plant a mismatch.
    """
    mirror = root / "mirror"
    entries = []
    for name, (path, content) in files.items():
        target = mirror / "someone" / "motions" / COMMIT / path
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_bytes(content)
        digest = (sha256 or {}).get(name, hashlib.sha256(content).hexdigest())
        entries.append({"file": name, "url": f"{GITHUB}/someone/motions/{COMMIT}/{path}", "sha256": digest,
                        "bytes": len(content), "source": "demo"})
    manifest = {"github_prefix": GITHUB, "sources": {"demo": {"licence": "CC0 (test data)"}},
                "sets": {"demo": entries}}
    return mirror.as_uri(), manifest


def write_manifest(path, manifest) -> str:
    path.write_text(json.dumps(manifest))
    return str(path)
