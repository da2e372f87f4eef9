"""3D shape context settings (Section 4): the one place their defaults and their on-disk name live.

The paper's descriptor: ``n_r * n_e * n_a = 4 * 5 * 10`` bins, ``R_min = 2 l_res``, ``R_max = h_sub / 3``,
soft votes, no normalisation. The config's ``descriptor`` section, ``voxpose describe --params`` and a model
file's descriptor all become a ``DescriptorSettings``; ``tag`` names its cached results directory.
"""

from dataclasses import asdict, dataclass, fields

from voxpose.errors import VoxposeError

FRAMES = ("world", "body")


@dataclass(frozen=True)
class DescriptorSettings:
    """Keyword arguments of ``ShapeContextTable`` and of the reference ``shape_contexts``, with the paper's values.

    n_r, n_e, n_a : radial, elevation and azimuth divisions (Eq. 4; elevation over 180, azimuth over 360 degrees).
    r_min : ``R_min`` in units of ``l_res`` (the paper: 2).
    r_max : ``R_max`` as a fraction of ``h_sub`` (the paper: 1/3).
    soft : soft voting with votes weighted by ``1 / cbrt(bin volume)`` (the paper) or hard voting.
    normalise : divide each descriptor by its sum (not in the paper).
    frame : ``world`` (the paper: bins aligned with the world's axes) or ``body`` (each frame described in the
        frame of its own hull's reference heading, ``voxpose.descriptors.body_frame``); applied by
        ``voxpose.descriptors.sequence.describe_sequence``, the one path of the workflow and of a model file.
    """

    n_r: int = 4
    n_e: int = 5
    n_a: int = 10
    r_min: float = 2.0
    r_max: float = 1 / 3
    soft: bool = True
    normalise: bool = False
    frame: str = "world"

    def __post_init__(self):
        if self.frame not in FRAMES:
            raise VoxposeError(f"descriptor: frame must be one of {', '.join(FRAMES)}, got {self.frame!r}")

    @classmethod
    def from_config(cls, cfg: dict, what: str = "descriptor") -> "DescriptorSettings":
        """From a ``descriptor``-style mapping; a key this class does not know is a one-line error naming it."""
        known = [f.name for f in fields(cls)]
        unknown = sorted(set(cfg) - set(known))
        if unknown:
            raise VoxposeError(f"{what}: unknown key {unknown[0]!r} (known: {', '.join(known)})")
        return cls(**cfg)

    def as_dict(self) -> dict:
        return asdict(self)

    def tag(self) -> str:
        """Readable directory name of the parameter set, e.g. ``R0.3333-r2-4x5x10-soft``."""
        tag = f"R{tag_number(self.r_max)}-r{tag_number(self.r_min)}-{self.n_r}x{self.n_e}x{self.n_a}"
        tag += "-soft" if self.soft else "-hard"
        tag += "-norm" if self.normalise else ""
        return tag + ("-body" if self.frame == "body" else "")


def tag_number(x) -> str:
    """A number as it appears in a directory tag: at most 4 significant digits, no trailing zeros."""
    return f"{x:.4g}"
