"""What the Snakemake workflow needs to know from the config, computed in one tested place.

The Snakefile stays thin: it asks this module which motions exist, which motions each experiment trains
and tests on, and how a parameter set is named on disk. Parameter sets are named by readable tags
(``R0.333-r2-4x5x10-soft``, ``mppca-K200-q5``) so that every point of a Figure 4 sweep is its own cached
target, and changing one value creates new targets instead of overwriting old ones.
"""

import fnmatch
import hashlib
from pathlib import Path

import jsonschema
import yaml

from voxpose.errors import VoxposeError


def validate_config(config: dict, schema_path) -> None:
    """Validate ``config`` against the JSON schema; raise a one-line ``VoxposeError`` naming the key."""
    schema = yaml.safe_load(Path(schema_path).read_text())
    validator = jsonschema.Draft202012Validator(schema)
    errors = sorted(validator.iter_errors(config), key=lambda e: list(e.absolute_path))
    if errors:
        err = errors[0]
        key = ".".join(str(p) for p in err.absolute_path) or "(top level)"
        raise VoxposeError(f"config key {key}: {err.message}")


def generated_motions(spec: dict) -> dict:
    """Names of the embedded generated set -> (kind, index, n_frames): ``{kind}_gen_{i:02d}``."""
    out = {}
    for kind, frames in spec.items():
        for i, n in enumerate(frames):
            out[f"{kind}_gen_{i:02d}"] = (kind, i, int(n))
    return out


def derived_motions(derived: list, source_names) -> dict:
    """Derived motion names -> (kind, source, params): ``spiral_<source>``, ``drunk_<source>`` or
    ``<source>_turnDDD`` (``motion.derive.derived_name``); the source must be a known motion."""
    from voxpose.motion.derive import derived_name

    out = {}
    source_names = set(source_names)
    for i, item in enumerate(derived):
        if item["source"] not in source_names:
            raise VoxposeError(f"config key derived.{i}.source: no motion named {item['source']!r} in bvh_dir")
        params = {k: v for k, v in item.items() if k not in ("kind", "source")}
        if item["kind"] == "turn" and "degrees" not in params:
            raise VoxposeError(f"config key derived.{i}: a turn needs 'degrees'")
        if item["kind"] != "turn" and params:
            raise VoxposeError(f"config key derived.{i}: {item['kind']} takes no {', '.join(sorted(params))}")
        out[derived_name(item["kind"], item["source"], params)] = (item["kind"], item["source"], params)
    return out


def bvh_dir_motions(bvh_dir) -> dict:
    """Motion name -> path for every ``*.bvh`` in ``bvh_dir`` (an empty or missing folder is an error)."""
    folder = Path(bvh_dir)
    if not folder.is_dir():
        raise VoxposeError(f"config key bvh_dir: {folder} is not a folder")
    files = sorted(folder.glob("*.bvh"))
    if not files:
        raise VoxposeError(f"config key bvh_dir: no .bvh files in {folder}")
    return {f.stem: f for f in files}


def match(patterns, names, key: str, *, allow_empty: bool = False) -> list:
    """Names matching any glob pattern, sorted; a pattern that matches nothing is an error naming ``key``."""
    names = sorted(names)
    out = set()
    for pattern in patterns:
        hits = fnmatch.filter(names, pattern)
        if not hits and not allow_empty:
            raise VoxposeError(f"config key {key}: pattern {pattern!r} matches no motion")
        out.update(hits)
    return sorted(out)


def resolve_experiment(name: str, exp: dict, names, key_prefix: str) -> dict:
    """Train and test motion lists of one experiment; overlapping sets are refused, naming the motions."""
    key = f"{key_prefix}.{name}"
    exclude = set(match(exp.get("exclude", []), names, f"{key}.exclude", allow_empty=True))
    train = [m for m in match(exp["train"], names, f"{key}.train") if m not in exclude]
    test = [m for m in match(exp["test"], names, f"{key}.test") if m not in exclude]
    if not train:
        raise VoxposeError(f"config key {key}.train: every training motion is excluded")
    if not test:
        raise VoxposeError(f"config key {key}.test: every test motion is excluded")
    overlap = sorted(set(train) & set(test))
    if overlap:
        raise VoxposeError(f"config key {key}: test motions also in training: {', '.join(overlap)}")
    return {"train": train, "test": test}


def _num(x) -> str:
    return f"{x:.4g}"


def descriptor_tag(cfg: dict) -> str:
    """Readable directory name of a descriptor parameter set (Section 4)."""
    tag = f"R{_num(cfg['r_max'])}-r{_num(cfg['r_min'])}-{cfg['n_r']}x{cfg['n_e']}x{cfg['n_a']}"
    tag += "-soft" if cfg["soft"] else "-hard"
    return tag + ("-norm" if cfg["normalise"] else "")


def feature_tag(method: str, cfg: dict) -> str:
    """Readable directory name of a feature transformation (Section 5): MPPCA or the K-means baseline."""
    if method == "mppca":
        return f"mppca-K{cfg['n_components']}-q{cfg['n_latent']}"
    if method == "kmeans":
        return f"kmeans-K{cfg['n_components']}-n{cfg['kmeans_neighbours']}"
    raise VoxposeError(f"unknown feature method {method!r} (mppca or kmeans)")


def code_hash(paths) -> str:
    """Short hash of source files: a rule's ``params`` entry so that an algorithm change reruns its jobs."""
    digest = hashlib.sha256()
    for path in sorted(str(p) for p in paths):
        digest.update(Path(path).read_bytes())
    return digest.hexdigest()[:16]


# --- the measured claims (issue 8) ---------------------------------------------------------------------------

_RIG_OVERRIDES = ("n_cameras", "radius", "height", "target_height", "focal_px", "width", "image_height")


def rig_camera_count(section: dict) -> int:
    """Number of cameras of a `rig`-style section: its calibration file's, else ``n_cameras``."""
    if section.get("file"):
        from voxpose.voxels.cameras import load_rig

        return len(load_rig(section["file"]))
    return int(section["n_cameras"])


def claims_rigs(claims: dict, rig: dict) -> dict:
    """Test rigs of ``claims.rigs`` as complete `rig` sections by name: overrides of ``rig``, or a file.

    Names must be unique, differ from the default rig's and not contain ``__`` (that marks degraded sets);
    ``claims.retrain`` may name only listed rigs.
    """
    out = {}
    for i, entry in enumerate(claims["rigs"]):
        name = entry["name"]
        if name == rig["name"] or name in out or "__" in name:
            why = "contains '__'" if "__" in name else "is used twice (or is the default rig's name)"
            raise VoxposeError(f"config key claims.rigs.{i}.name: {name!r} {why}")
        section = dict(rig, name=name, file=entry.get("file"))
        section |= {k: entry[k] for k in _RIG_OVERRIDES if k in entry}
        out[name] = section
    if "__" in rig["name"]:
        raise VoxposeError(f"config key rig.name: {rig['name']!r} must not contain '__' (it marks degraded sets)")
    for i, name in enumerate(claims["retrain"]):
        if name not in out:
            raise VoxposeError(f"config key claims.retrain.{i}: {name!r} is not one of claims.rigs")
    return out


def degraded_sets(claims: dict, rig_name: str, n_cameras: int) -> dict:
    """Voxel sets of the robustness study by name ``{rig}__{kind}{level}__min{views}``.

    One per degradation level and carving rule ``min_views = n_cameras - k`` (k in ``claims.carving_drop``),
    plus the clean silhouettes (kind ``none``) under each rule. Value: ``{"kind", "level", "band_px",
    "min_views"}`` (``voxpose.voxels.degrade``).
    """
    out = {}
    for i, drop in enumerate(claims["carving_drop"]):
        views = n_cameras - drop
        if views < 1:
            raise VoxposeError(f"config key claims.carving_drop.{i}: {drop} leaves no view of {n_cameras}")
        levels = [("none", 0)] + [(kind, lv) for kind, lvs in claims["degradations"].items() for lv in lvs]
        for kind, level in levels:
            name = f"{rig_name}__{'clean' if kind == 'none' else kind}{level:g}__min{views}"
            out[name] = {"kind": kind, "level": level, "band_px": claims["band_px"], "min_views": views}
    return out


def contour_tag(cfg: dict) -> str:
    """Readable name of a 2D shape-context parameter set (``voxpose.descriptors.contour``)."""
    return f"sc2d-p{cfg['n_points']}-{cfg['n_r']}x{cfg['n_theta']}-r{_num(cfg['r_inner'])}-{_num(cfg['r_outer'])}"


def at_tag(cfg: dict, cameras) -> str:
    """Readable name of an Agarwal & Triggs codebook on one camera (an index) or ``"all"`` cameras."""
    return f"at-K{cfg['n_centres']}-n{cfg['neighbours']}-" + ("all" if cameras == "all" else f"cam{cameras}")
