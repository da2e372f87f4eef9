"""``voxpose fit-silhouette-features``: the Agarwal & Triggs K-means codebook on training 2D shape contexts."""

from voxpose.cli.common import add_output, parse_json, parse_params, seed
from voxpose.config_schema import section
from voxpose.errors import VoxposeError

NAME = "fit-silhouette-features"
HELP = "fit the A&T K-means codebook on training shape contexts"


def add_arguments(p):
    p.add_argument("contexts", nargs="+", help="shape-context files (HDF5) of the training motions")
    p.add_argument("--params", required=True, help="JSON: the config's `claims.at` section")
    p.add_argument("--cameras", required=True, help='JSON: "all" or a list of camera indices')
    p.add_argument("--seed", type=seed, default=0)
    add_output(p)


def run(args):
    from voxpose.descriptors.file import contour_layout, read_contours
    from voxpose.features.silhouette import ContourSource, fit_codebook

    params = parse_params(args.params, schema=section("claims", "at"))
    cameras = parse_json(args.cameras, "--cameras")
    if cameras != "all" and not (isinstance(cameras, list) and all(type(c) is int and c >= 0 for c in cameras)):
        raise VoxposeError(f'--cameras: expected "all" or a list of camera indices, got {args.cameras}')
    training = []
    for path in args.contexts:
        offsets, meta = contour_layout(path)
        training.append(ContourSource(offsets, meta["n_cameras"], lambda path=path: read_contours(path)[0]))
    model = fit_codebook(training, cameras, params, args.seed)
    model.save(args.output)
