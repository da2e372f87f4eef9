"""``voxpose data-fetch``: download a real motion-capture set, verified against pinned checksums."""

import logging
import os

from voxpose.errors import VoxposeError

log = logging.getLogger("voxpose")

NAME = "data-fetch"
HELP = "download a real BVH set (bvh, bvh-library) into a folder, verified against pinned SHA-256"
BASE_URL_VARIABLE = "VOXPOSE_DATA_BASE_URL"


def add_arguments(p):
    p.add_argument("set", nargs="?", help="the set to download (see --list)")
    p.add_argument("dir", nargs="?", help="the folder to write the files into (created if missing)")
    p.add_argument("--list", action="store_true", help="print the sets, their sizes and licences, and exit")
    p.add_argument(
        "--base-url",
        default=os.environ.get(BASE_URL_VARIABLE),
        help="replace https://raw.githubusercontent.com with this prefix (a mirror laid out as "
        f"<owner>/<repo>/<commit>/<path>; default ${BASE_URL_VARIABLE})",
    )
    p.add_argument("--manifest", help="a manifest JSON to use instead of the one shipped with voxpose")


def run(args):
    from voxpose.io.data_fetch import describe_sets, fetch_set, load_manifest

    manifest = load_manifest(args.manifest)
    if args.list:
        print("\n".join(describe_sets(manifest)))
        return
    if not args.set or not args.dir:
        raise VoxposeError("data-fetch needs a set and a folder (voxpose data-fetch bvh data/bvh), or --list")
    fetch_set(manifest, args.set, args.dir, base_url=args.base_url)
