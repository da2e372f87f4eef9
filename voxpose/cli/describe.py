"""``voxpose describe``: voxels -> 3D shape contexts at the basis voxels (Section 4)."""

import logging

from voxpose.cli.common import add_output, parse_params
from voxpose.config_schema import section

log = logging.getLogger("voxpose")

NAME = "describe"
HELP = "voxels -> 3D shape contexts at the basis voxels (HDF5)"


def add_arguments(p):
    p.add_argument("voxels", help="voxel file (HDF5) from `voxpose voxelize` or `voxpose carve`")
    p.add_argument("--params", default="{}", help="JSON: the config's `descriptor` section")
    add_output(p)


def run(args):
    from voxpose.descriptors.file import write_descriptors
    from voxpose.descriptors.sequence import describe_sequence
    from voxpose.descriptors.settings import DescriptorSettings
    from voxpose.voxels.sequence import read_voxels
    from voxpose.voxels.settings import VoxelSettings

    cfg = parse_params(args.params, schema=section("descriptor", required=False))
    settings = DescriptorSettings.from_config(cfg, "--params")
    seq, meta, _ = read_voxels(args.voxels)
    n_basis = None  # the world frame keeps the carving's basis voxels; the body frame draws its own
    if settings.frame == "body":
        n_basis = VoxelSettings.from_config(meta.get("params") or {}, f"{args.voxels}: params").n_basis
    descriptors, h0 = describe_sequence(seq, settings, n_basis=n_basis, threads=args.threads)
    basis_ijk = [ijk[basis] for ijk, _, basis in map(seq.frame, range(seq.n_frames))]  # the world grid's
    out_meta = {
        "params": cfg,
        "motion": meta.get("motion"),
        "kind": meta.get("kind"),
        "l_res": seq.l_res,
        "h_sub": seq.h_sub,
        "empty": seq.empty.tolist(),
    }
    write_descriptors(args.output, descriptors, basis_ijk, out_meta, h0 if settings.frame == "body" else None)
    n_desc = sum(map(len, descriptors))
    log.info("describe: %d frames, %d descriptors -> %s", seq.n_frames, n_desc, args.output)
