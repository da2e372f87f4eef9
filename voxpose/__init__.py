"""voxpose: regression-based human pose from voxel data (Sun et al., BMVC 2006)."""

__version__ = "0.1.0"
