"""Silhouettes degraded as real segmentation degrades them, to measure robustness (issue 8; Section 6 claims).

The paper argues that voxels make the regressor robust on real data; these degradations let us measure it on
synthetic data whose ground truth is known. Each is deterministic per seed: a frame's random draws come from
``numpy.random.default_rng([seed, kind, 0, frame])`` (a sequence's from ``[seed, kind, 1]``), so a frame's
degradation does not depend on the frames processed before it. Kinds and what their ``level`` means (``none``,
level 0: the clean silhouettes):

``flip``
    Boundary noise: every pixel within ``band_px`` pixels (Euclidean) of the silhouette's boundary, inside or
    outside, flips with probability ``level`` (so ``level`` is the expected fraction of the band that changes).
``morph``
    Morphological error of ``level`` pixels: dilation (``level > 0``) or erosion (``level < 0``) by a disc of
    radius ``|level|``, in every view (a segmentation threshold set too low or too high).
``limb``
    A missing limb part in one view: in one camera, drawn per frame, the ``level`` outermost segments of one
    limb, drawn per frame, are not rendered (1: the hand or foot; 2: with the forearm or shin; 3: the whole arm
    or leg), as when a limb against a background of its colour is lost. Pixels the rest of the body covers stay.
``calibration``
    A calibration error in one camera, drawn per sequence: the silhouettes are exact but the carving uses that
    camera rotated by ``level`` degrees about a random axis through its centre (at 4 m, 1 degree moves the
    subject's image by about 7 cm). Translation errors of a few centimetres act like small rotations.

``Degradation.apply`` changes a frame's silhouettes; ``Degradation.carving_rig`` gives the rig the carving uses;
``voxelize_degraded`` is ``voxpose.voxels.voxelize.voxelize_motion`` with a degradation between rendering and carving.
"""

from dataclasses import dataclass

import numpy as np

from voxpose.errors import VoxposeError
from voxpose.motion.rotations import axis_angle_to_matrix
from voxpose.voxels.body import Ellipsoids, body_ellipsoids
from voxpose.voxels.cameras import Camera, Rig
from voxpose.voxels.morphology import dilate, erode
from voxpose.voxels.render import render_silhouettes
from voxpose.voxels.voxelize import subject_shifts, voxelize_silhouettes

KINDS = ("none", "flip", "morph", "limb", "calibration")
_KIND_CODE = {kind: i for i, kind in enumerate(KINDS)}
# each limb's segments from its extremity inwards (names of voxpose.voxels.body.SEGMENTS)
LIMBS = (
    ("lhand", "lforearm", "lupperarm"),
    ("rhand", "rforearm", "rupperarm"),
    ("lfoot", "lshin", "lthigh"),
    ("rfoot", "rshin", "rthigh"),
)


def disc(radius: int) -> np.ndarray:
    """Boolean disc structuring element: offsets (dy, dx) with dy^2 + dx^2 <= radius^2."""
    r = np.arange(-radius, radius + 1)
    return r[:, None] ** 2 + r[None, :] ** 2 <= radius**2


def boundary_band(mask: np.ndarray, band_px: int) -> np.ndarray:
    """Pixels of a (H, W) mask within ``band_px`` of its boundary: dilation minus erosion by a disc."""
    se = disc(band_px)
    return dilate(mask, se) & ~erode(mask, se)


def flip_boundary(sil: np.ndarray, probability: float, band_px: int, rng) -> np.ndarray:
    """Silhouettes (C, H, W) with each pixel of every view's boundary band flipped with ``probability``."""
    out = sil.copy()
    for c, mask in enumerate(sil):
        rows, cols = np.flatnonzero(mask.any(axis=1)), np.flatnonzero(mask.any(axis=0))
        if rows.size == 0:
            continue
        # the band lies within band_px of the silhouette's bounding box: work on that window only
        r0, c0 = max(rows[0] - band_px - 1, 0), max(cols[0] - band_px - 1, 0)
        window = np.s_[r0 : rows[-1] + band_px + 2, c0 : cols[-1] + band_px + 2]
        band = boundary_band(mask[window], band_px)
        out[c][window] ^= band & (rng.random(band.shape) < probability)
    return out


def morph(sil: np.ndarray, pixels: int) -> np.ndarray:
    """Every view dilated (``pixels > 0``) or eroded (``pixels < 0``) by a disc of radius ``|pixels|``."""
    if pixels == 0:
        return sil.copy()
    se = disc(abs(pixels))
    return (dilate if pixels > 0 else erode)(sil, se)


def drop_limb(sil: np.ndarray, ellipsoids: Ellipsoids, rig: Rig, n_segments: int, rng) -> np.ndarray:
    """Silhouettes with the ``n_segments`` outermost segments of one limb missing in one view (both drawn)."""
    limb = LIMBS[rng.integers(len(LIMBS))]
    camera = int(rng.integers(len(rig)))
    gone = set(limb[:n_segments])
    keep = [i for i, name in enumerate(ellipsoids.names) if name not in gone]
    rest = Ellipsoids(
        tuple(ellipsoids.names[i] for i in keep),
        ellipsoids.centres[keep],
        ellipsoids.rotations[keep],
        ellipsoids.radii[keep],
    )
    out = sil.copy()
    out[camera] = render_silhouettes(rest, Rig(rig.name, [rig[camera]]))[0]
    return out


def rotate_camera(camera: Camera, degrees: float, axis) -> Camera:
    """``camera`` rotated by ``degrees`` about ``axis`` (camera frame) through its centre (centre unchanged)."""
    q = axis_angle_to_matrix(np.asarray(axis, dtype=float), np.radians(degrees))
    return Camera(camera.name, camera.K, q @ camera.R, q @ camera.t, camera.width, camera.height, camera.dist)


@dataclass(frozen=True)
class Degradation:
    """One degradation (module docstring): ``kind``, ``level``, ``band_px`` (``flip`` only) and ``seed``."""

    kind: str
    level: float
    seed: int
    band_px: int = 2

    def __post_init__(self):
        if self.kind not in KINDS:
            raise VoxposeError(f"degradation: unknown kind {self.kind!r} (known: {', '.join(KINDS)})")
        level = self.level
        checks = {
            "none": level == 0,
            "flip": 0 <= level <= 1,
            "morph": float(level).is_integer(),
            "limb": float(level).is_integer() and 1 <= level <= 3,
            "calibration": 0 <= level < 45,
        }
        if not checks[self.kind]:
            raise VoxposeError(f"degradation {self.kind}: level {level!r} is out of range (voxpose.voxels.degrade)")
        if self.band_px < 1:
            raise VoxposeError(f"degradation: band_px must be at least 1, got {self.band_px!r}")

    def _rng(self, frame: int | None):
        """Draws of one frame, or (``None``) of the whole sequence."""
        stream = [1] if frame is None else [0, frame]
        return np.random.default_rng([self.seed, _KIND_CODE[self.kind], *stream])

    def apply(self, frame: int, sil: np.ndarray, ellipsoids: Ellipsoids, rig: Rig) -> np.ndarray:
        """Degraded silhouettes (C, H, W) of frame ``frame`` (its body model ``ellipsoids``, seen by ``rig``)."""
        if self.kind == "flip":
            return flip_boundary(sil, self.level, self.band_px, self._rng(frame))
        if self.kind == "morph":
            return morph(sil, int(self.level))
        if self.kind == "limb":
            return drop_limb(sil, ellipsoids, rig, int(self.level), self._rng(frame))
        return sil

    def carving_rig(self, rig: Rig) -> Rig:
        """The rig the carving uses: ``rig`` itself, or with one camera rotated (``calibration``)."""
        if self.kind != "calibration":
            return rig
        rng = self._rng(None)
        camera = int(rng.integers(len(rig)))
        axis = rng.normal(size=3)
        cameras = list(rig.cameras)
        cameras[camera] = rotate_camera(rig[camera], self.level, axis / np.linalg.norm(axis))
        return Rig(rig.name, cameras)


def posed_body(motion, rig: Rig, *, proportions=None, variation=None, follow_subject: bool = True):
    """(Ellipsoids (F frames), shifts (F, 3)): the body model placed as ``voxelize_motion`` places it."""
    shifts = subject_shifts(motion, rig) if follow_subject else np.zeros((motion.n_frames, 3))
    return body_ellipsoids(motion, proportions, variation).translated(shifts), shifts


def voxelize_degraded(
    motion, rig: Rig, degradation: Degradation, *, proportions=None, variation=None, follow_subject=True, **carving
):
    """Render ``motion`` into ``rig``, degrade every frame, carve with ``degradation.carving_rig(rig)``.

    ``carving``: ``l_res_fraction``, ``min_views``, ``n_basis``, ``seed`` of ``voxels.voxelize.voxelize_silhouettes``.
    h_sub is measured on the degraded data, as it would be on real data.
    """
    ellipsoids, shifts = posed_body(
        motion, rig, proportions=proportions, variation=variation, follow_subject=follow_subject
    )

    def frames():
        for f in range(motion.n_frames):
            body = ellipsoids.frame(f)
            yield degradation.apply(f, render_silhouettes(body, rig), body, rig)

    return voxelize_silhouettes(
        frames(), degradation.carving_rig(rig), n_frames=motion.n_frames, shifts=shifts, name=motion.name, **carving
    )
