"""Download the real motion-capture sets: every file verified against a pinned SHA-256, written atomically.

The manifest (``data_sets.json`` beside this module) lists, per set, each file under the name the config
expects, its raw GitHub URL at a pinned commit, its SHA-256 and size, and its source (licence, credit). A file
appears in the target folder only after its checksum matched, so an interrupted or corrupted download never
leaves a file the workflow would read; a file already present with the right checksum is not fetched again.
"""

import hashlib
import http.client
import json
import logging
import re
import urllib.error
import urllib.request
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

from voxpose.errors import VoxposeError
from voxpose.io.atomic import atomic_path

log = logging.getLogger("voxpose")

MANIFEST = "data_sets.json"
CHUNK = 1 << 16
TIMEOUT_S = 60
_SHA256 = re.compile(r"[0-9a-f]{64}")


@dataclass(frozen=True)
class DataFile:
    """One file of a set: its name in the target folder, where it comes from and what it must hash to."""

    file: str
    url: str
    sha256: str
    bytes: int
    source: str


def load_manifest(path=None) -> dict:
    """The manifest at ``path``, or the one shipped with the package; its structure checked."""
    where = str(path) if path else f"voxpose/io/{MANIFEST}"
    try:
        text = Path(path).read_text() if path else resources.files("voxpose.io").joinpath(MANIFEST).read_text()
        manifest = json.loads(text)
    except (OSError, json.JSONDecodeError) as err:
        raise VoxposeError(f"manifest {where}: {err}") from None
    if not isinstance(manifest, dict) or not isinstance(manifest.get("sets"), dict):
        raise VoxposeError(f"manifest {where}: expected an object with a 'sets' mapping")
    for name in manifest["sets"]:
        set_files(manifest, name, where)
    return manifest


def set_files(manifest: dict, name: str, where: str = "manifest") -> list[DataFile]:
    """The files of set ``name``, each entry checked (a plain file name, a 64-digit hex SHA-256, a known source)."""
    sets = manifest["sets"]
    if name not in sets:
        raise VoxposeError(f"unknown data set {name!r} (known: {', '.join(sorted(sets))})")
    sources = manifest.get("sources", {})
    out = []
    for i, entry in enumerate(sets[name]):
        try:
            item = DataFile(**entry)
        except TypeError as err:
            raise VoxposeError(f"{where}: sets.{name}.{i}: {err}") from None
        if Path(item.file).name != item.file or item.file in ("", ".", ".."):
            raise VoxposeError(f"{where}: sets.{name}.{i}: file {item.file!r} is not a plain file name")
        if not _SHA256.fullmatch(item.sha256):
            raise VoxposeError(f"{where}: sets.{name}.{i} ({item.file}): sha256 is not 64 lower-case hex digits")
        if item.source not in sources:
            raise VoxposeError(f"{where}: sets.{name}.{i} ({item.file}): unknown source {item.source!r}")
        out.append(item)
    return out


def mirrored(url: str, prefix: str, base_url: str | None) -> str:
    """``url`` with its ``prefix`` (the GitHub raw prefix) replaced by ``base_url``, so a mirror works."""
    if not base_url or not url.startswith(prefix):
        return url
    return base_url.rstrip("/") + url[len(prefix.rstrip("/")) :]


def sha256_of(path) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as f:
        while chunk := f.read(CHUNK):
            digest.update(chunk)
    return digest.hexdigest()


def _download(url: str, target: Path, item: DataFile) -> None:
    """Stream ``url`` to ``target`` atomically; a download error or a checksum mismatch leaves nothing."""
    with atomic_path(target) as tmp:
        digest = hashlib.sha256()
        try:
            with urllib.request.urlopen(url, timeout=TIMEOUT_S) as response, open(tmp, "wb") as out:
                while chunk := response.read(CHUNK):
                    digest.update(chunk)
                    out.write(chunk)
        except (urllib.error.URLError, http.client.HTTPException, OSError, ValueError) as err:
            reason = err if isinstance(err, urllib.error.HTTPError) else getattr(err, "reason", None) or err
            raise VoxposeError(f"cannot download {url}: {' '.join(str(reason).split())}") from None
        if digest.hexdigest() != item.sha256:
            raise VoxposeError(
                f"{item.file}: checksum mismatch for {url} (got sha256 {digest.hexdigest()}, expected {item.sha256});"
                " nothing written"
            )


def fetch_set(manifest: dict, name: str, dest, base_url: str | None = None) -> dict:
    """Download every file of set ``name`` into ``dest``; return how many were fetched and skipped."""
    files = set_files(manifest, name)
    dest = Path(dest)
    prefix = manifest.get("github_prefix", "https://raw.githubusercontent.com")
    fetched = skipped = 0
    for position, item in enumerate(files, 1):
        target = dest / item.file
        if target.is_file():
            if sha256_of(target) == item.sha256:
                skipped += 1
                continue
            log.info("%s: present with another checksum, fetching it again", target)
        url = mirrored(item.url, prefix, base_url)
        _download(url, target, item)
        fetched += 1
        log.info("%s: fetched and verified (%d of %d) from %s", target, position, len(files), url)
    log.info("data set %s: %d fetched, %d already present -> %s", name, fetched, skipped, dest)
    return {"fetched": fetched, "skipped": skipped}


def describe_sets(manifest: dict) -> list[str]:
    """One line per set: name, file count, size and the sources' licences."""
    lines = []
    for name in manifest["sets"]:
        files = set_files(manifest, name)
        size_mb = sum(f.bytes for f in files) / 1e6
        used = dict.fromkeys(f.source for f in files)
        licences = "; ".join(f"{s}: {manifest['sources'][s].get('licence', '?')}" for s in used)
        lines.append(f"{name}\t{len(files)} files\t{size_mb:.1f} MB\t{licences}")
    return lines
