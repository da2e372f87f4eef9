"""Every frame of a voxel sequence described: 3D shape contexts at its basis voxels over its surface voxels.

One path for the workflow (``voxpose describe``) and for a trained model on new data (``voxpose.apply.predict``).
A frame whose hull is empty is a gap: it gets no descriptors (a (0, bins) array), never invented ones.
With ``frame: body`` each frame is described in the frame of its hull's reference heading
(``voxpose.descriptors.body_frame``), which is returned with the descriptors; in the world frame it is 0. The
headings' senses are chosen over the whole sequence (``body_frame.continuous_headings``), so the hulls are read
twice: once for the headings, once for the descriptors.
"""

import numpy as np

from voxpose.descriptors.body_frame import body_voxels, continuous_headings, heading_axis
from voxpose.descriptors.lut import ShapeContextTable
from voxpose.descriptors.settings import DescriptorSettings
from voxpose.errors import VoxposeError
from voxpose.voxels.sequence import VoxelSequence


def describe_sequence(
    seq: VoxelSequence, settings: DescriptorSettings, *, n_basis: int | None = None, threads: int = 1
):
    """``(descriptors, h0)``: (B_f, bins) float64 descriptors of every frame f (Section 4), with the subject
    height in voxels ``h_sub / l_res`` of the sequence, and (F,) the reference headings in degrees (0 in the
    world frame and at gaps). In the body frame the basis voxels are drawn again on the turned grid, about
    ``n_basis`` of them (the carving's setting); the world frame uses the sequence's own."""
    if settings.frame == "body" and n_basis is None:
        raise VoxposeError("describe: body-frame descriptors need the carving's n_basis")
    table = ShapeContextTable(seq.h_sub / seq.l_res, **settings.as_dict())
    out = [np.zeros((0, table.n_bins)) for _ in range(seq.n_frames)]
    h0 = np.zeros(seq.n_frames)
    carved = np.flatnonzero(~seq.empty)
    pivots = {}
    if settings.frame == "body":
        axes, scores = np.zeros(len(carved)), np.zeros(len(carved))
        for k, f in enumerate(carved):
            axes[k], scores[k], pivots[f] = heading_axis(seq.frame(f)[0], seq.h_sub / seq.l_res)
        h0[carved] = continuous_headings(axes, scores, carved)

    def pairs():
        for f in carved:
            ijk, surface, basis = seq.frame(f)
            if settings.frame == "world":
                yield ijk[surface], ijk[basis]
                continue
            body, body_surface, body_basis = body_voxels(ijk, n_basis, h0[f], pivots[f])
            yield body[body_surface], body_basis

    for f, desc in zip(carved, table.describe_frames(pairs(), threads=threads), strict=True):
        out[f] = desc
    return out, h0
