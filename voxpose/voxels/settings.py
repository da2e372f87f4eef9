"""Carving settings (Section 4): the one place their defaults live.

The config's ``voxels`` section, ``voxpose carve``'s options, ``voxpose voxelize`` and a model file's carving
settings all become a ``VoxelSettings``: voxels of side ``l_res = h_sub * l_res_fraction`` (the paper's h/60),
a voxel occupied when inside the silhouettes of all views (``min_views=None``) or of at least ``min_views``,
``n_basis`` basis voxels per frame (Figure 2). ``follow_subject``, ``proportions`` and ``variation`` concern
rendering the body model of synthetic data only, so a model file keeps the carving part (``carving``) and the
basis seed.
"""

from dataclasses import asdict, dataclass, field, fields

from voxpose.errors import VoxposeError
from voxpose.voxels.body_variation import BodyVariation


@dataclass(frozen=True)
class VoxelSettings:
    """How silhouettes become voxels, and (for synthetic data) how the body model is placed and sized."""

    l_res_fraction: float = 1 / 60
    min_views: int | None = None
    n_basis: int = 200
    follow_subject: bool = True
    proportions: dict = field(default_factory=dict)
    variation: dict = field(default_factory=dict)

    def __post_init__(self):
        if isinstance(self.l_res_fraction, bool) or not (
            isinstance(self.l_res_fraction, int | float) and 0 < self.l_res_fraction < 1
        ):
            raise VoxposeError(f"voxels: l_res_fraction must lie in (0, 1), got {self.l_res_fraction!r}")
        if self.min_views is not None and (isinstance(self.min_views, bool) or not isinstance(self.min_views, int)
                                           or self.min_views < 1):  # fmt: skip
            raise VoxposeError(f"voxels: min_views must be null or a positive integer, got {self.min_views!r}")
        if isinstance(self.n_basis, bool) or not isinstance(self.n_basis, int) or self.n_basis < 1:
            raise VoxposeError(f"voxels: n_basis must be a positive integer, got {self.n_basis!r}")
        object.__setattr__(self, "l_res_fraction", float(self.l_res_fraction))
        unknown = sorted(set(self.variation) - {f.name for f in fields(BodyVariation)})
        if unknown:
            raise VoxposeError(f"voxels.variation: unknown key {unknown[0]!r} (known: girth_sd, length_sd)")
        BodyVariation(**self.variation)  # checks the values

    @classmethod
    def from_config(cls, cfg: dict, what: str = "voxels") -> "VoxelSettings":
        """From a ``voxels``-style mapping; a key this class does not know is a one-line error naming it."""
        known = {f.name for f in fields(cls)}
        unknown = sorted(set(cfg) - known)
        if unknown:
            raise VoxposeError(f"{what}: unknown key {unknown[0]!r} (known: {', '.join(sorted(known))})")
        return cls(**{k: v for k, v in cfg.items() if not (k == "proportions" and v is None)})

    def body_variation(self, motion_name: str, seed: int) -> dict | None:
        """This motion's body variation factors (``voxels.body_variation``), None when off."""
        return BodyVariation(**self.variation).draw(motion_name, seed)

    def carving(self) -> dict:
        """Keyword arguments of ``voxelize_silhouettes`` these settings fix (everything but the body model's)."""
        return {"l_res_fraction": self.l_res_fraction, "min_views": self.min_views, "n_basis": self.n_basis}

    def as_dict(self) -> dict:
        return asdict(self)


DEFAULTS = VoxelSettings()
