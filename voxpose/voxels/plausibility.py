"""Checks that a real studio's rig and hull describe a person in voxpose's world (metres, Y up, floor at 0).

A rig read in the wrong unit or with the wrong up axis carves a hull all the same, and ``predict`` then returns
a normal-looking pose; these checks stop such a run with one line that names the likely fix:

* up axis: the cameras' image "up" (minus the camera's y axis, in the world) must on average point up the world
  (+Y); a rig whose images see world +Y as down was calibrated with another up axis (``--up``);
* subject height: h_sub (Section 4) outside 1.0-2.3 m means another length unit (``--unit``) or a wrong rig;
* coverage: cameras spanning less than 180 degrees around the capture centre (the largest horizontal gap
  between their azimuths exceeds 180 degrees) leave ghost volume in the hull: a warning, not an error.
"""

import logging

import numpy as np

from voxpose.errors import VoxposeError

log = logging.getLogger(__name__)

H_SUB_RANGE = (1.0, 2.3)  # metres: people, standing, with some margin


def check_rig(rig, label: str) -> None:
    """The up-axis check (error) and the coverage check (warning) of the module docstring."""
    image_up = np.mean([-cam.R[1] for cam in rig.cameras], axis=0)
    if image_up[1] <= 0:
        raise VoxposeError(f"{label}: the cameras' images show world +Y pointing down (mean image-up "
                           f"{np.round(image_up, 2).tolist()}): the calibration has another up axis; "
                           "import it with --up (e.g. --up +z or --up -y)")  # fmt: skip
    if len(rig) > 1:
        offsets = np.array([cam.centre for cam in rig.cameras]) - rig.target
        azimuths = np.sort(np.degrees(np.arctan2(offsets[:, 0], offsets[:, 2])) % 360.0)
        gap = np.max(np.diff(np.r_[azimuths, azimuths[0] + 360.0]))
        if 360.0 - gap < 180.0:
            log.warning("%s: the cameras span %.0f deg around the subject (< 180): the hull will hold ghost "
                        "volume (extra voxels the views cannot exclude)", label, 360.0 - gap)  # fmt: skip


def check_height(h_sub: float, label: str) -> None:
    """The subject-height check of the module docstring."""
    lo, hi = H_SUB_RANGE
    if not lo <= h_sub <= hi:
        raise VoxposeError(f"{label}: the subject is {h_sub:.3f} m tall (h_sub), outside {lo}-{hi} m: the rig's "
                           "length unit or up axis is likely wrong; import it with --unit (e.g. mm, dm) and --up")
