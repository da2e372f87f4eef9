"""Reading and writing BVH motion-capture files: the hierarchy and the per-frame channel values, as they are.

A BVH file has two parts. ``HIERARCHY`` is a tree of joints written depth first: ``ROOT``/``JOINT name``
blocks in braces, each with an ``OFFSET x y z`` (the joint's position in its parent's frame, file units),
a ``CHANNELS n name...`` line and optionally an ``End Site`` block (an offset with no channels: the tip of
a chain). ``MOTION`` gives ``Frames: F``, ``Frame Time: dt`` (seconds) and F lines of numbers, one per
frame, with each joint's channel values in hierarchy order. Channel names are ``X/Y/Zposition`` and
``X/Y/Zrotation`` (degrees); a joint has 0 or 3 of each kind, in any order, and the order of its rotation
channels is its Euler order (``Zrotation Yrotation Xrotation`` -> ``"ZYX"``, ``R = Rz @ Ry @ Rx``; see
``voxpose.motion.rotations``). Nothing is interpreted here; ``voxpose.motion.bvh_kinematics`` gives the poses.

The parser is a small hand-written tokenizer that keeps line numbers, so every problem in a file is
reported as a ``VoxposeError`` of the form ``path:line: what is wrong``.
"""

import codecs
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from voxpose.errors import VoxposeError
from voxpose.io.atomic import atomic_path

POSITION_CHANNELS = ("Xposition", "Yposition", "Zposition")
ROTATION_CHANNELS = ("Xrotation", "Yrotation", "Zrotation")
CHANNEL_NAMES = POSITION_CHANNELS + ROTATION_CHANNELS


@dataclass
class BvhJoint:
    """One joint of the hierarchy.

    Attributes
    ----------
    name : joint name as written in the file.
    parent : index into ``Bvh.joints`` of the parent, -1 for the root.
    offset : (3,) float64 position in the parent's frame, file units.
    channels : channel names in file column order, e.g. ``("Zrotation", "Yrotation", "Xrotation")``.
    end_site : (3,) ``End Site`` offset in this joint's frame if the joint has one, else None.
    """

    name: str
    parent: int
    offset: np.ndarray
    channels: tuple[str, ...]
    end_site: np.ndarray | None = None


@dataclass
class Bvh:
    """A parsed BVH file.

    Attributes
    ----------
    joints : the joints in depth-first file order (a parent always precedes its children).
    frame_time : seconds between frames.
    motion : (F, total_channels) float64 channel values in file column order (degrees, file units).
    """

    joints: list[BvhJoint]
    frame_time: float
    motion: np.ndarray

    @property
    def n_frames(self) -> int:
        return int(self.motion.shape[0])


def channel_slices(bvh: Bvh) -> list[slice]:
    """The column range of each joint's channels in ``io.bvh.motion``, in joint order."""
    out, start = [], 0
    for joint in bvh.joints:
        out.append(slice(start, start + len(joint.channels)))
        start += len(joint.channels)
    return out


def rotation_order(joint: BvhJoint) -> str | None:
    """The joint's Euler order read from its CHANNELS (``"ZYX"`` etc.), or None if it has no rotation."""
    order = "".join(c[0] for c in joint.channels if c in ROTATION_CHANNELS)
    return order or None


def joint_columns(bvh: Bvh, index: int) -> tuple[list[int] | None, list[int] | None]:
    """Columns of joint ``index``'s position channels (X, Y, Z order) and rotation channels (file order).

    Either is None when the joint has no channels of that kind.
    """
    joint = bvh.joints[index]
    start = channel_slices(bvh)[index].start
    pos = [start + joint.channels.index(c) for c in POSITION_CHANNELS if c in joint.channels]
    rot = [start + i for i, c in enumerate(joint.channels) if c in ROTATION_CHANNELS]
    return (pos or None), (rot or None)


class _Tokens:
    """Whitespace-separated tokens of the HIERARCHY part, each with its 1-based line number."""

    def __init__(self, path, lines: list[str], stop: int):
        self.path = path
        self.items = [(tok, n + 1) for n in range(stop) for tok in lines[n].split()]
        self.pos = 0
        self.end_line = stop

    def error(self, line: int, message: str) -> VoxposeError:
        return VoxposeError(f"{self.path}:{line}: {message}")

    def peek(self) -> tuple[str | None, int]:
        if self.pos < len(self.items):
            return self.items[self.pos]
        return None, self.end_line

    def next(self, what: str) -> tuple[str, int]:
        tok, line = self.peek()
        if tok is None:
            raise self.error(line, f"unexpected end of HIERARCHY, expected {what}")
        self.pos += 1
        return tok, line

    def expect(self, word: str) -> int:
        tok, line = self.next(repr(word))
        if tok != word:
            raise self.error(line, f"expected {word!r}, found {tok!r}")
        return line

    def rest_of_line(self, line: int) -> list[str]:
        out = []
        while self.pos < len(self.items) and self.items[self.pos][1] == line and self.items[self.pos][0] != "{":
            out.append(self.items[self.pos][0])
            self.pos += 1
        return out

    def floats(self, count: int, what: str) -> np.ndarray:
        values = []
        for _ in range(count):
            tok, line = self.next(what)
            values.append(_number(tok, lambda m, line=line: self.error(line, f"{what}: {m}")))
        return np.array(values, dtype=np.float64)


def _number(token: str, error) -> float:
    try:
        value = float(token)
    except ValueError:
        raise error(f"{token!r} is not a number") from None
    if not np.isfinite(value):
        raise error(f"{token!r} is not a finite number")
    return value


def _parse_channels(tokens: _Tokens, joint_name: str) -> tuple[str, ...]:
    tok, line = tokens.next("the number of channels")
    if not (tok.isascii() and tok.isdigit()):
        raise tokens.error(line, f"CHANNELS of {joint_name!r}: expected a channel count, found {tok!r}")
    channels = []
    for _ in range(int(tok)):
        name, name_line = tokens.next("a channel name")
        if name not in CHANNEL_NAMES:
            raise tokens.error(
                name_line,
                f"unknown channel {name!r} in joint {joint_name!r} (known: {', '.join(CHANNEL_NAMES)})",
            )
        if name in channels:
            raise tokens.error(name_line, f"channel {name!r} repeated in joint {joint_name!r}")
        channels.append(name)
    for kind in (POSITION_CHANNELS, ROTATION_CHANNELS):
        if sum(c in kind for c in channels) not in (0, 3):
            raise tokens.error(
                line, f"joint {joint_name!r} must have all three or none of {', '.join(kind)}: {channels}"
            )
    return tuple(channels)


def _parse_joint(tokens: _Tokens, name: str, name_line: int, parent: int, joints: list[BvhJoint]) -> None:
    """Parse the braced body of joint ``name`` (after its name) and its descendants into ``joints``."""
    tokens.expect("{")
    index = len(joints)
    joint = BvhJoint(name=name, parent=parent, offset=None, channels=None)
    joints.append(joint)
    while True:
        tok, line = tokens.next(f"'}}' closing joint {name!r} (line {name_line})")
        if tok == "}":
            break
        if tok == "OFFSET":
            if joint.offset is not None:
                raise tokens.error(line, f"second OFFSET in joint {name!r}")
            joint.offset = tokens.floats(3, f"OFFSET of {name!r}")
        elif tok == "CHANNELS":
            if joint.channels is not None:
                raise tokens.error(line, f"second CHANNELS in joint {name!r}")
            joint.channels = _parse_channels(tokens, name)
        elif tok == "JOINT":
            words = tokens.rest_of_line(line)
            if not words:
                raise tokens.error(line, "JOINT without a name")
            _parse_joint(tokens, " ".join(words), line, index, joints)
        elif tok == "End":
            tokens.expect("Site")
            if joint.end_site is not None:
                raise tokens.error(line, f"second End Site in joint {name!r}")
            tokens.expect("{")
            tokens.expect("OFFSET")
            joint.end_site = tokens.floats(3, f"End Site OFFSET of {name!r}")
            tokens.expect("}")
        else:
            raise tokens.error(line, f"unexpected {tok!r} in joint {name!r}")
    if joint.offset is None:
        raise tokens.error(name_line, f"joint {name!r} has no OFFSET")
    if joint.channels is None:
        raise tokens.error(name_line, f"joint {name!r} has no CHANNELS")


def _parse_hierarchy(path, lines: list[str], motion_line: int) -> list[BvhJoint]:
    tokens = _Tokens(path, lines, motion_line)
    tokens.expect("HIERARCHY")
    tok, line = tokens.next("ROOT")
    if tok != "ROOT":
        raise tokens.error(line, f"expected ROOT, found {tok!r}")
    words = tokens.rest_of_line(line)
    if not words:
        raise tokens.error(line, "ROOT without a name")
    joints: list[BvhJoint] = []
    _parse_joint(tokens, " ".join(words), line, -1, joints)
    tok, line = tokens.peek()
    if tok is not None:
        raise tokens.error(line, f"unexpected {tok!r} after the root joint's closing brace (one ROOT only)")
    return joints


def _header_value(path, lines, index: int, words: tuple[str, ...]) -> tuple[str, int]:
    """Read ``words value`` (e.g. ``Frames: 317``) from the next non-blank line at or after ``index``."""
    while index < len(lines) and not lines[index].strip():
        index += 1
    label = " ".join(words)
    if index >= len(lines):
        raise VoxposeError(f"{path}:{len(lines)}: missing {label!r} after MOTION")
    parts = lines[index].split()
    if tuple(parts[: len(words)]) != words or len(parts) != len(words) + 1:
        raise VoxposeError(f"{path}:{index + 1}: expected '{label} <value>', found {lines[index].strip()!r}")
    return parts[-1], index + 1


def _motion_header(path, lines: list[str], start: int) -> tuple[int, float, int]:
    """``(Frames, Frame Time, index of the first frame line)``; ``start`` is the index of the line after MOTION.

    A file of 0 frames is refused here: no stage can use a motion without frames, and a derived copy of one
    would be another empty file.
    """
    value, index = _header_value(path, lines, start, ("Frames:",))
    if not (value.isascii() and value.isdigit()):
        raise VoxposeError(f"{path}:{index}: Frames: expected a whole number, found {value!r}")
    n_frames = int(value)
    if n_frames == 0:
        raise VoxposeError(f"{path}:{index}: Frames: 0, the file has no frames (a motion needs at least one)")
    value, index = _header_value(path, lines, index, ("Frame", "Time:"))
    frame_time = _number(value, lambda m: VoxposeError(f"{path}:{index}: Frame Time: {m}"))
    if frame_time <= 0:
        raise VoxposeError(f"{path}:{index}: Frame Time must be positive, got {value}")
    return n_frames, frame_time, index


def _parse_frames(path, lines: list[str], index: int, n_frames: int, n_channels: int) -> np.ndarray:
    """The (Frames, channels) values of the frame lines from line ``index`` (0-based) on."""
    rows = [(n + 1, line) for n, line in enumerate(lines[index:], start=index) if line.strip()]
    if len(rows) < n_frames:
        last = rows[-1][0] if rows else index
        raise VoxposeError(f"{path}:{last}: truncated MOTION: Frames: {n_frames} but {len(rows)} frame lines")
    if len(rows) > n_frames:
        raise VoxposeError(f"{path}:{rows[n_frames][0]}: more frame lines than Frames: {n_frames} ({len(rows)} lines)")
    split = [line.split() for _, line in rows]
    for (number, _), values in zip(rows, split, strict=True):
        if len(values) != n_channels:
            raise VoxposeError(f"{path}:{number}: frame line has {len(values)} values, expected {n_channels}")
    try:
        motion = np.array(split, dtype=np.float64).reshape(n_frames, n_channels)
        if np.all(np.isfinite(motion)):
            return motion
    except ValueError:
        pass
    # slow path, only to name the offending line
    for (number, _), values in zip(rows, split, strict=True):
        for tok in values:
            _number(tok, lambda m, number=number: VoxposeError(f"{path}:{number}: frame value {m}"))
    raise VoxposeError(f"{path}:{index}: frame values could not be read as numbers")


# byte-order marks of the encodings a BVH file is sometimes saved in (UTF-32 first: its LE mark starts UTF-16's)
_BYTE_ORDER_MARKS = (
    (codecs.BOM_UTF32_LE, "UTF-32 (little-endian)", "UTF-32"),
    (codecs.BOM_UTF32_BE, "UTF-32 (big-endian)", "UTF-32"),
    (codecs.BOM_UTF16_LE, "UTF-16 (little-endian)", "UTF-16"),
    (codecs.BOM_UTF16_BE, "UTF-16 (big-endian)", "UTF-16"),
)


def _encoding_error(path, encoding: str, iconv: str) -> VoxposeError:
    return VoxposeError(
        f"{path}: the file is {encoding} text; BVH files are read as UTF-8 (or ASCII): convert it, e.g. "
        f"iconv -f {iconv} -t UTF-8 {path} > converted.bvh"
    )


def _read_lines(path: Path) -> list[str]:
    """The file's text lines, for every reader alike: UTF-8 (a byte-order mark is skipped), split at ``\\n``
    only (a ``\\r`` before it dropped), so a line number means the same line to ``read_bvh`` and
    ``read_duration`` and to a text editor. Other encodings, binary data and an empty file are refused by name.
    """
    try:
        data = path.read_bytes()
    except OSError as err:
        raise VoxposeError(f"{path}: cannot read BVH file: {err.strerror or err}") from None
    if not data:
        raise VoxposeError(f"{path}: empty file (0 bytes), not a BVH file")
    for mark, encoding, iconv in _BYTE_ORDER_MARKS:
        if data.startswith(mark):
            raise _encoding_error(path, encoding, iconv)
    data = data.removeprefix(codecs.BOM_UTF8)
    nul = data.find(b"\0")
    if nul >= 0:
        sample = data[:4096]
        for zeros, encoding in ((sample[1::2], "UTF-16 (little-endian)"), (sample[0::2], "UTF-16 (big-endian)")):
            if zeros.count(0) > 0.9 * len(zeros):  # ASCII text in UTF-16 without a byte-order mark
                raise _encoding_error(path, encoding + " without a byte-order mark", "UTF-16")
        line = data.count(b"\n", 0, nul) + 1
        raise VoxposeError(f"{path}:{line}: binary data (a NUL byte), not a BVH text file")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as err:
        line = data.count(b"\n", 0, err.start) + 1
        raise VoxposeError(
            f"{path}:{line}: byte 0x{data[err.start]:02x} is not UTF-8: BVH files are read as UTF-8 (or ASCII); "
            f"convert the file from its encoding, e.g. iconv -f LATIN1 -t UTF-8 {path} > converted.bvh"
        ) from None
    lines = text.split("\n")
    if lines[-1] == "":
        lines.pop()  # the end of the last line, not a line
    return [line.removesuffix("\r") for line in lines]


def _parse_header(path, lines: list[str]) -> tuple[list[BvhJoint], int, float, int]:
    """``(joints, Frames, Frame Time, index of the first frame line)``: everything but the frame lines."""
    motion_line = next((n for n, line in enumerate(lines) if line.split()[:1] == ["MOTION"]), None)
    if motion_line is None:
        raise VoxposeError(f"{path}:{len(lines)}: no MOTION section")
    if lines[motion_line].split() != ["MOTION"]:
        raise VoxposeError(f"{path}:{motion_line + 1}: unexpected text after MOTION")
    joints = _parse_hierarchy(path, lines, motion_line)
    return joints, *_motion_header(path, lines, motion_line + 1)


def read_bvh(path) -> Bvh:
    """Parse a BVH file; every problem raises ``VoxposeError("path:line: ...")``."""
    path = Path(path)
    lines = _read_lines(path)
    joints, n_frames, frame_time, index = _parse_header(path, lines)
    n_channels = sum(len(j.channels) for j in joints)
    motion = _parse_frames(path, lines, index, n_frames, n_channels)
    return Bvh(joints=joints, frame_time=frame_time, motion=motion)


def read_duration(path) -> tuple[int, float]:
    """``(Frames, Frame Time)`` of a BVH file, its header checked as ``read_bvh`` checks it, frames not read.

    Cheap enough to size workflow jobs before they run (``workflow/rules/common.smk``: every file's header is
    read while the workflow starts), with the same messages and line numbers as ``read_bvh``: a header error
    is reported once, before any job runs, as ``voxpose motion`` would report it.
    """
    path = Path(path)
    _, n_frames, frame_time, _ = _parse_header(path, _read_lines(path))
    return n_frames, frame_time


def _check_writable(bvh: Bvh) -> None:
    """Errors that would make ``write_bvh`` produce a file that does not read back as ``bvh``."""
    joints = bvh.joints
    if not joints or joints[0].parent != -1:
        raise VoxposeError("write_bvh: the first joint must be the root (parent -1)")
    children: list[list[int]] = [[] for _ in joints]
    for i, joint in enumerate(joints):
        if not joint.name.strip() or joint.name != " ".join(joint.name.split()) or "{" in joint.name:
            raise VoxposeError(f"write_bvh: joint {i}: name {joint.name!r} cannot be written to BVH")
        if i and not 0 <= joint.parent < i:
            raise VoxposeError(f"write_bvh: joint {joint.name!r}: parent {joint.parent} must precede it")
        if i:
            children[joint.parent].append(i)
        unknown = [c for c in joint.channels if c not in CHANNEL_NAMES]
        if unknown or len(set(joint.channels)) != len(joint.channels):
            raise VoxposeError(f"write_bvh: joint {joint.name!r}: bad channels {joint.channels}")
        for kind in (POSITION_CHANNELS, ROTATION_CHANNELS):
            if sum(c in kind for c in joint.channels) not in (0, 3):
                raise VoxposeError(f"write_bvh: joint {joint.name!r}: needs 0 or 3 of {', '.join(kind)}")
        for what, vec in (("offset", joint.offset), ("end_site", joint.end_site)):
            if vec is not None and (np.shape(vec) != (3,) or not np.all(np.isfinite(vec))):
                raise VoxposeError(f"write_bvh: joint {joint.name!r}: {what} must be 3 finite numbers")
    order, stack = [], [0]
    while stack:
        i = stack.pop()
        order.append(i)
        stack.extend(reversed(children[i]))
    if order != list(range(len(joints))):
        raise VoxposeError("write_bvh: joints are not in depth-first order (a subtree is interleaved)")
    n_channels = sum(len(j.channels) for j in joints)
    motion = np.asarray(bvh.motion)
    if motion.ndim != 2 or motion.shape[1] != n_channels or motion.shape[0] < 1:
        raise VoxposeError(f"write_bvh: motion has shape {motion.shape}, expected (frames >= 1, {n_channels})")
    if not np.all(np.isfinite(motion)):
        raise VoxposeError("write_bvh: motion holds NaN or infinite values")
    if not (np.isfinite(bvh.frame_time) and bvh.frame_time > 0):
        raise VoxposeError(f"write_bvh: frame_time must be positive, got {bvh.frame_time}")


def _hierarchy_lines(bvh: Bvh, fmt) -> list[str]:
    children: list[list[int]] = [[] for _ in bvh.joints]
    for i, joint in enumerate(bvh.joints[1:], start=1):
        children[joint.parent].append(i)
    out = ["HIERARCHY"]

    def emit(i: int, depth: int) -> None:
        joint, pad = bvh.joints[i], "\t" * depth
        out.append(f"{pad}{'ROOT' if i == 0 else 'JOINT'} {joint.name}")
        out.append(pad + "{")
        out.append(f"{pad}\tOFFSET {' '.join(fmt(v) for v in joint.offset)}")
        out.append(f"{pad}\tCHANNELS {len(joint.channels)} {' '.join(joint.channels)}".rstrip())
        for child in children[i]:
            emit(child, depth + 1)
        if joint.end_site is not None:
            out.extend(
                [
                    f"{pad}\tEnd Site",
                    f"{pad}\t{{",
                    f"{pad}\t\tOFFSET {' '.join(fmt(v) for v in joint.end_site)}",
                ]
            )
            out.append(f"{pad}\t}}")
        out.append(pad + "}")

    emit(0, 0)
    return out


def _format_rows(motion: np.ndarray, precision: int) -> str:
    """Frame lines, one per row, each value printed with ``precision`` significant digits."""
    fmt = f"%.{precision}g"
    return "".join(" ".join(fmt % v for v in row) + "\n" for row in motion.tolist())


def write_bvh(bvh: Bvh, path, precision: int = 6) -> None:
    """Write ``bvh`` to ``path`` atomically (``io.atomic.atomic_path``): all of it or, on any error, nothing.

    Every number is printed with ``precision`` significant digits (``%.{precision}g``), so reading the
    file back gives exactly the printed values. The frame time is printed with 10 significant digits.
    """
    if not isinstance(precision, int) or not 1 <= precision <= 17:
        raise VoxposeError(f"write_bvh: precision must be an integer in 1..17, got {precision!r}")
    _check_writable(bvh)
    number = f"%.{precision}g"
    lines = _hierarchy_lines(bvh, lambda v: number % v)
    lines += ["MOTION", f"Frames: {bvh.n_frames}", f"Frame Time: {bvh.frame_time:.10g}"]
    with atomic_path(path) as tmp, open(tmp, "w", encoding="utf-8", newline="\n") as handle:
        handle.write("\n".join(lines) + "\n")
        handle.write(_format_rows(np.asarray(bvh.motion, dtype=np.float64), precision))
