"""A trained pipeline as one file: everything ``voxpose predict`` needs, and nothing of the training data.

One HDF5 file (layout ``model``, format ``MODEL_FORMAT``) bundles, for one experiment's trained pipeline:

* ``voxels``: the rig-independent carving settings (``l_res_fraction`` of the subject height, ``min_views``,
  ``n_basis`` and the basis seed): new silhouettes are carved exactly as the training ones were (Section 4);
* ``descriptor``: the 3D shape context parameters (Section 4), with the frame the model was trained in
  (``frame``: ``world`` or ``body``, ``voxpose.descriptors.body_frame``; files without it are ``world``);
* group ``feature_model``: the fitted MPPCA (Eq. 5) or K-means transformation (``FeatureModel.to_arrays``);
* group ``regressor``: the pose PCA (Eq. 1) and the MVRVM (Section 3):
  ``voxpose.regression.stored.regressor_arrays``, the same arrays
  ``voxpose regress`` writes to ``regressor.h5``, and ``heading`` (``voxpose.regression.pose_encoding``);
* group ``skeleton``: the BVH output skeleton (``voxpose.motion.output_skeleton``: the training subjects' body);
* ``provenance``: experiment, rig, training motions, the run's test errors, voxpose version.

The rig is not part of a model: the descriptors are measured in units of the subject's height and do not
depend on where the cameras stand, so a model applies to any calibrated rig (its silhouettes' quality aside).
Loading checks the layout, the store's layout version and ``MODEL_FORMAT``: a file of another format, a
damaged file or another voxpose file is a one-line ``VoxposeError`` naming the file.
"""

from dataclasses import dataclass, field

from voxpose.errors import VoxposeError
from voxpose.features.model import FeatureModel
from voxpose.io.hdf5 import read_groups, write_groups
from voxpose.motion.output_skeleton import OutputSkeleton
from voxpose.regression.mvrvm import MVRVM
from voxpose.regression.pose_encoding import ENCODINGS
from voxpose.regression.pose_space import PosePCA
from voxpose.regression.stored import regressor_arrays, regressor_from_arrays
from voxpose.voxels.settings import VoxelSettings

LAYOUT = "model"
MODEL_FORMAT = 1
VOXEL_KEYS = ("l_res_fraction", "min_views", "n_basis", "seed")


@dataclass
class PoseModel:
    """A trained pipeline: carving settings, descriptor parameters, features, pose PCA, MVRVM, skeleton.

    ``voxels`` holds ``VOXEL_KEYS``; ``descriptor`` the keyword arguments of ``ShapeContextTable``.
    """

    voxels: dict
    descriptor: dict
    features: FeatureModel
    pca: PosePCA
    mvrvm: MVRVM
    heading: str
    skeleton: OutputSkeleton
    fps: float = 30.0
    provenance: dict = field(default_factory=dict)

    def __post_init__(self):
        missing = [k for k in VOXEL_KEYS if k not in self.voxels]
        if missing:
            raise VoxposeError(f"model: voxel settings lack {', '.join(missing)}")
        if self.heading not in ENCODINGS:
            raise VoxposeError(f"model: heading must be one of {', '.join(ENCODINGS)}, got {self.heading!r}")


def save_model(path, model: PoseModel) -> None:
    """Write ``model`` atomically."""
    regressor, regressor_meta = regressor_arrays(model.pca, model.mvrvm)
    groups = {
        "feature_model": model.features.to_arrays(),
        "regressor": (regressor, regressor_meta | {"heading": model.heading}),
        "skeleton": ({"offsets": model.skeleton.offsets, "end_lengths": model.skeleton.end_lengths}, {}),
    }
    meta = {"voxels": model.voxels, "descriptor": model.descriptor, "fps": model.fps, "provenance": model.provenance}
    write_groups(path, LAYOUT, groups, meta, attrs={"model_format": MODEL_FORMAT})


def _check_format(path):
    def check(attrs):
        found = int(attrs.get("model_format", -1))
        if found != MODEL_FORMAT:
            raise VoxposeError(f"{path}: model file of format {found}, this voxpose reads format {MODEL_FORMAT}")

    return check


def load_model(path) -> PoseModel:
    """Read a model file (module docstring); any problem is a one-line ``VoxposeError`` naming ``path``."""
    groups, meta = read_groups(path, LAYOUT, check=_check_format(path))
    try:
        pca, mvrvm = regressor_from_arrays(*groups["regressor"])
        skeleton = groups["skeleton"][0]
        features = FeatureModel.from_arrays(*groups["feature_model"]).compiled()  # predict loads numba anyway
        return PoseModel(
            voxels=meta["voxels"],
            descriptor=meta["descriptor"],
            features=features,
            pca=pca,
            mvrvm=mvrvm,
            heading=groups["regressor"][1]["heading"],
            skeleton=OutputSkeleton(skeleton["offsets"], skeleton["end_lengths"]),
            fps=float(meta["fps"]),
            provenance=meta.get("provenance", {}),
        )
    except KeyError as err:
        raise VoxposeError(f"{path}: damaged model file (missing {err})") from None


def voxel_settings(cfg: dict, seed: int) -> dict:
    """The model's voxel settings from the config's ``voxels`` section and the master seed."""
    return VoxelSettings.from_config(cfg).carving() | {"seed": int(seed)}
