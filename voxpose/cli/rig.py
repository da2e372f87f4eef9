"""``voxpose rig``: the calibration file of the configured camera rig (Section 6: cameras on a circle), and
``voxpose rig import``: a real studio's calibration (OpenCV files or projection matrices) as a rig file."""

import logging

from voxpose.cli.common import add_output, finite_number, parse_params, positive_integer
from voxpose.config_schema import section
from voxpose.errors import VoxposeError

log = logging.getLogger("voxpose")

NAME = "rig"
HELP = "write the calibration file of the configured camera rig; `rig import` reads a real studio's calibration"


def add_arguments(p):
    p.add_argument("--params", help="JSON: the config's `rig` section")
    p.add_argument("-o", "--output", help="output file")
    sub = p.add_subparsers(dest="rig_action", metavar="import")
    imp = sub.add_parser("import", help="OpenCV FileStorage YAML/XML or 3x4 projection matrices -> rig file",
                         description=__doc__.splitlines()[1])  # fmt: skip
    imp.add_argument("calibration", nargs="+", help="OpenCV YAML/XML files (one per camera or one for all), "
                     "or one text file of 3x4 projection matrices with --projections")  # fmt: skip
    imp.add_argument("--projections", action="store_true", help="the file holds 3x4 projection matrices")
    imp.add_argument("--unit", default="m", help="length unit of the calibration: m, dm, cm, mm or metres per unit")
    imp.add_argument("--up", default="+y", help="the calibration world's up axis: +x -x +y -y +z -z (default +y; write "
                     "a negative one as --up=-z)")
    imp.add_argument("--floor", type=finite_number, help="floor height along the up axis, in the calibration's unit "
                     "(default: estimated from the first frame of --silhouettes)")  # fmt: skip
    imp.add_argument("--size", help="image size WxH when the files do not give it")
    imp.add_argument("--silhouettes", help="silhouette folder to estimate the floor from (its first frame)")
    imp.add_argument("--pattern", help="silhouette file pattern (voxpose.voxels.silhouettes)")
    imp.add_argument("--name", help="rig name (default: the output's stem)")
    add_output(imp)
    imp.add_argument("--log", help="also write progress to this file")
    imp.add_argument("--threads", type=positive_integer, default=1, help="threads for numerical libraries (default 1)")


def _size(text):
    if text is None:
        return None
    try:
        width, height = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise VoxposeError(f"--size {text!r}: expected WIDTHxHEIGHT in pixels, e.g. 1280x720") from None
    if width <= 0 or height <= 0:
        raise VoxposeError(f"--size {text!r}: width and height must be positive")
    return width, height


def run(args):
    if args.rig_action == "import":
        return run_import(args)
    from voxpose.voxels.cameras import rig_from_config, save_rig

    if not args.params or not args.output:
        raise VoxposeError("rig: --params and -o are required (or use `voxpose rig import`)")
    rig = rig_from_config(parse_params(args.params, schema=section("rig")))
    save_rig(rig, args.output)
    log.info("rig %s: %d cameras -> %s", rig.name, len(rig), args.output)


def run_import(args):
    import json
    from pathlib import Path

    from voxpose.io.atomic import atomic_path
    from voxpose.voxels.calibration import cameras_from_projections, cameras_from_storage, estimate_floor
    from voxpose.voxels.cameras import rig_from_dict, unit_scale, up_rotation

    scale, size = unit_scale(args.unit), _size(args.size)
    up_rotation(args.up)  # refuse a bad --up before reading anything
    if args.projections:
        if len(args.calibration) != 1:
            raise VoxposeError("--projections: give one text file holding every camera's 3x4 matrix")
        cameras = cameras_from_projections(args.calibration[0], size)
    else:
        cameras = cameras_from_storage(args.calibration, size)
    out = Path(args.output)
    data = {"name": args.name or out.stem, "unit": args.unit, "up": args.up, "floor": 0.0, "cameras": cameras}
    rig = rig_from_dict(data, str(args.calibration[0]))
    if args.floor is not None:
        data["floor"] = args.floor
    elif args.silhouettes:
        from voxpose.voxels.silhouettes import iter_silhouette_folder

        first = next(iter_silhouette_folder(args.silhouettes, rig, pattern=args.pattern))
        data["floor"] = estimate_floor(rig, first, scale)
        log.info("rig import: floor estimated from the first frame of %s (lowest occupied 5 cm layer): %.6g %s "
                 "along %s; pass --floor to set it", args.silhouettes, data["floor"], args.unit, args.up)  # fmt: skip
    else:
        log.warning("rig import: no --floor and no --silhouettes to estimate it from: floor taken at 0 %s along %s",
                    args.unit, args.up)  # fmt: skip
    rig = rig_from_dict(data, str(args.calibration[0]))
    with atomic_path(out) as tmp:
        tmp.write_text(json.dumps(data, indent=2) + "\n")
    log.info("rig import: %d cameras (%s) -> %s", len(rig), ", ".join(rig.names), out)
