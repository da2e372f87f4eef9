"""The subcommands of ``voxpose``: each reads its inputs, calls the library and writes its outputs atomically.

``COMMANDS`` maps a name to ``(help, add_arguments(parser), run(args))``; ``voxpose.cli`` builds the parser
from it. Library modules are imported inside each ``run`` so that ``voxpose --help`` stays fast.
"""

import json
import logging

from .errors import VoxposeError

log = logging.getLogger("voxpose")


def _params(text: str, what: str = "--params") -> dict:
    try:
        value = json.loads(text)
    except json.JSONDecodeError as err:
        raise VoxposeError(f"{what}: not valid JSON ({err})") from None
    if not isinstance(value, dict):
        raise VoxposeError(f"{what}: expected a JSON object")
    return value


def _out(p):
    p.add_argument("-o", "--output", required=True, help="output file")


# --- motions ---


def _generate_args(p):
    p.add_argument("--kind", required=True, choices=["walk", "drunk", "spiral", "jog", "jump"])
    p.add_argument("--index", type=int, required=True, help="sequence number within its kind")
    p.add_argument("--frames", type=int, required=True)
    p.add_argument("--seed", type=int, required=True, help="master seed of the generated set")
    _out(p)


def _generate(args):
    from .bvh import write_bvh
    from .motion_generator import generate_motion, sequence_seed

    seed = sequence_seed(args.seed, args.kind, args.index)
    write_bvh(generate_motion(args.kind, seed=seed, n_frames=args.frames), args.output)
    log.info("generated %s (%d frames, seed %d) -> %s", args.kind, args.frames, seed, args.output)


def _derive_args(p):
    p.add_argument("source", help="a real straight walk (BVH)")
    p.add_argument("--kind", required=True, choices=["spiral", "drunk"])
    p.add_argument("--seed", type=int, required=True)
    _out(p)


def _derive(args):
    from .bvh import read_bvh, write_bvh
    from .derived_motions import drunk_from_walk, spiral_from_walk

    transform = spiral_from_walk if args.kind == "spiral" else drunk_from_walk
    write_bvh(transform(read_bvh(args.source), seed=args.seed), args.output)
    log.info("derived a %s walk from %s -> %s", args.kind, args.source, args.output)


def _motion_args(p):
    p.add_argument("bvh", help="BVH file")
    p.add_argument("--params", default="{}", help="JSON: the config's `motions` section")
    _out(p)


def _motion(args):
    from .motion_loader import load_motion
    from .store import write_motion

    cfg = _params(args.params)
    motion = load_motion(
        args.bvh,
        fps=cfg.get("fps", 30.0),
        unit_scale=cfg.get("unit_scale"),
        joint_map=cfg.get("joint_map"),
        drop_reference_frame=cfg.get("drop_reference_frame", "auto"),
    )
    write_motion(args.output, motion)
    log.info(
        "%s: %d frames at %g fps, height %.2f m", motion.name, motion.n_frames, motion.fps, motion.height
    )


COMMANDS = {
    "generate": ("write one motion of the embedded default set as BVH", _generate_args, _generate),
    "derive": ("derive a spiral or drunken walk from a real straight walk (BVH)", _derive_args, _derive),
    "motion": ("BVH -> canonical 42-angle poses (HDF5)", _motion_args, _motion),
}
