"""A corpus of malformed BVH files built from one valid file: truncations, wrong counts, non-numeric values,
bad channels, other encodings, binary data, an empty file and a motion of 0 frames (issue 21), plus two
well-formed variants that must still load (CRLF line ends, a UTF-8 byte-order mark).

Each malformed file is listed with where its error is (``header``: found while the workflow sizes its jobs;
``frames``: found when the motion is loaded), the 1-based line the message must name (None: no line, e.g. an
empty file) and a fragment of the message.
"""

import functools
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from voxpose.io.bvh import write_bvh
from voxpose.motion.generate import default_motion

N_FRAMES = 12


@dataclass(frozen=True)
class Case:
    name: str
    data: bytes
    part: str | None  # "header", "frames", or None for a file that must load
    line: int | None
    fragment: str


def valid_text() -> str:
    """A valid BVH file's text: a generated walk of ``N_FRAMES`` frames."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "walk_valid.bvh"
        write_bvh(default_motion("walk", 0, n_frames=N_FRAMES, seed=0), path)
        return path.read_text()


def _line_of(lines: list[str], prefix: str, nth: int = 0) -> int:
    """0-based index of the ``nth`` line whose stripped text starts with ``prefix``."""
    return [i for i, line in enumerate(lines) if line.strip().startswith(prefix)][nth]


def _token(lines: list[str], index: int, k: int, new: str) -> bytes:
    """The file with token ``k`` of line ``index`` replaced by ``new`` (``new`` may hold two tokens)."""
    out = list(lines)
    tokens = out[index].split()
    tokens[k] = new
    out[index] = " ".join(tokens)
    return ("\n".join(out) + "\n").encode()


def _replace(lines: list[str], index: int, old: str, new: str) -> bytes:
    assert old in lines[index]
    out = list(lines)
    out[index] = out[index].replace(old, new, 1)
    return ("\n".join(out) + "\n").encode()


@functools.cache
def corpus() -> tuple[Case, ...]:
    """The 19 malformed files and the 2 well-formed variants, malformed first (``write_corpus`` writes them)."""
    text = valid_text()
    lines = text.splitlines()
    motion = _line_of(lines, "MOTION")
    frames, time = motion + 1, motion + 2
    first, last = motion + 3, len(lines) - 1
    spine_channels = _line_of(lines, "CHANNELS", 1)
    spine_offset = _line_of(lines, "OFFSET", 1)
    garbage = np.random.default_rng(0).bytes(3000)
    join = lambda ls: ("\n".join(ls) + "\n").encode()  # noqa: E731
    cases = [
        Case("truncated_header", join(lines[:40]), "header", 40, "no MOTION section"),
        Case("truncated_frames", join(lines[:-3]), "frames", last - 2,
             f"truncated MOTION: Frames: {N_FRAMES} but {N_FRAMES - 3} frame lines"),
        Case("truncated_midline", text[: text.rindex(" ", 0, len(text) - 40)].encode(), "frames", last + 1,
             "frame line has"),
        Case("missing_root", _replace(lines, 1, "ROOT", "JOINT"), "header", 2, "expected ROOT, found 'JOINT'"),
        Case("channel_count_low", _replace(lines, spine_channels, "CHANNELS 3", "CHANNELS 2"), "header",
             spine_channels + 1, "must have all three or none"),
        Case("channel_count_high", _replace(lines, spine_channels, "CHANNELS 3", "CHANNELS 4"), "header",
             spine_channels + 2, "unknown channel 'JOINT'"),
        Case("channel_unknown", _replace(lines, spine_channels, "Xrotation", "Wrotation"), "header",
             spine_channels + 1, "unknown channel 'Wrotation'"),
        Case("channel_repeated", _replace(lines, spine_channels, "Xrotation", "Zrotation"), "header",
             spine_channels + 1, "repeated"),
        Case("offset_word", _replace(lines, spine_offset, "OFFSET 0 ", "OFFSET zero "), "header", spine_offset + 1,
             "'zero' is not a number"),
        Case("frame_value_word", _token(lines, first + 4, 7, "1.2.3"), "frames", first + 5, "'1.2.3' is not a number"),
        Case("frame_value_count", _token(lines, first + 2, 0, "1 2"), "frames", first + 3,
             "frame line has"),
        Case("frames_too_many", _replace(lines, frames, f"Frames: {N_FRAMES}", f"Frames: {N_FRAMES + 5}"),
             "frames", last + 1, "truncated MOTION"),
        Case("frames_too_few", _replace(lines, frames, f"Frames: {N_FRAMES}", f"Frames: {N_FRAMES - 2}"),
             "frames", last, "more frame lines than Frames"),
        Case("frames_word", _replace(lines, frames, f"Frames: {N_FRAMES}", "Frames: twelve"), "header",
             frames + 1, "expected a whole number"),
        Case("frame_time_zero", _replace(lines, time, lines[time].split()[-1], "0"), "header", time + 1,
             "Frame Time must be positive"),
        Case("zero_frames", join([*lines[:frames], "Frames: 0", lines[time]]), "header", frames + 1,
             "no frames"),
        Case("utf16", text.encode("utf-16"), "header", None, "UTF-16"),
        Case("binary", garbage, "header", garbage.count(b"\n", 0, garbage.index(b"\0")) + 1, "binary data"),
        Case("empty", b"", "header", None, "empty"),
        Case("crlf", text.replace("\n", "\r\n").encode(), None, None, ""),
        Case("utf8_bom", text.encode("utf-8-sig"), None, None, ""),
    ]  # fmt: skip
    return tuple(cases)


def write_corpus(folder: Path, cases=None) -> dict[str, Path]:
    """Write ``cases`` (default: all) as ``folder/walk_<name>.bvh``; case name -> path."""
    folder.mkdir(parents=True, exist_ok=True)
    out = {}
    for case in corpus() if cases is None else cases:
        out[case.name] = folder / f"walk_{case.name}.bvh"
        out[case.name].write_bytes(case.data)
    return out
