"""What the Snakemake workflow needs to know from the config, computed in one tested place.

The Snakefile stays thin: it asks this module which motions exist, which motions each experiment trains
and tests on, and how a parameter set is named on disk. Parameter sets are named by readable tags
(``R0.333-r2-4x5x10-soft``, ``mppca-K200-q5``) so that every point of a Figure 4 sweep is its own cached
target, and changing one value creates new targets instead of overwriting old ones.
"""

import fnmatch
import hashlib
from pathlib import Path

from voxpose.config_schema import config_schema, validate
from voxpose.descriptors.settings import DescriptorSettings, tag_number
from voxpose.errors import VoxposeError
from voxpose.features.fit_keys import FIT_KEYS


def validate_config(config: dict) -> None:
    """Validate ``config`` against the schema (``voxpose.config_schema``); a one-line ``VoxposeError`` naming the
    key. Number-like strings at numeric keys (YAML 1.1's ``1e-3``) become numbers, in place."""
    validate(config, config_schema(), "config")


def generated_motions(spec: dict) -> dict:
    """Names of the embedded generated set -> (kind, index, n_frames): ``{kind}_gen_{i:02d}``."""
    out = {}
    for kind, frames in spec.items():
        for i, n in enumerate(frames):
            out[f"{kind}_gen_{i:02d}"] = (kind, i, int(n))
    return out


def derived_motions(derived: list, source_names) -> tuple[dict, list]:
    """Derived motion names -> (kind, source, params): ``spiral_<source>``, ``drunk_<source>`` or
    ``<source>_turnDDD`` (``motion.derive.derived_name``), and the names left out because their source is not
    among ``source_names`` (the shipped list names the shared data's walks; any other folder lacks them)."""
    from voxpose.motion.derive import derived_name

    out, absent = {}, []
    source_names = set(source_names)
    for i, item in enumerate(derived):
        params = {k: v for k, v in item.items() if k not in ("kind", "source")}
        if item["kind"] == "turn" and "degrees" not in params:
            raise VoxposeError(f"config key derived.{i}: a turn needs 'degrees'")
        if item["kind"] != "turn" and params:
            raise VoxposeError(f"config key derived.{i}: {item['kind']} takes no {', '.join(sorted(params))}")
        name = derived_name(item["kind"], item["source"], params)
        if item["source"] in source_names:
            out[name] = (item["kind"], item["source"], params)
        else:
            absent.append(name)
    return out, absent


def motion_settings(name: str, motions: dict) -> dict:
    """The settings that load motion ``name`` (``voxpose motion --params``): the ``motions`` section's keys, with
    those of the first ``motions.overrides`` entry whose ``files`` glob patterns match the name replacing them.

    One folder can mix skeleton families this way: an entry maps one family, and the motions no entry matches
    keep the section's settings (with ``joint_map: null``, the built-in presets detect their own families).
    The workflow passes each motion its own settings, so editing an entry reruns only the motions it matches.
    """
    settings = {k: v for k, v in motions.items() if k != "overrides"}
    for entry in motions.get("overrides") or []:
        if any(fnmatch.fnmatch(name, pattern) for pattern in entry["files"]):
            return settings | {k: v for k, v in entry.items() if k != "files"}
    return settings


def bvh_dir_motions(bvh_dir) -> dict:
    """Motion name -> path for every ``*.bvh`` in ``bvh_dir``, a folder or a list of folders.

    A missing folder, a folder without BVH files, or a motion name (file stem) found in two folders is an error.
    """
    folders = [bvh_dir] if isinstance(bvh_dir, str | Path) else list(bvh_dir)
    out = {}
    for i, item in enumerate(folders):
        key = "bvh_dir" if isinstance(bvh_dir, str | Path) else f"bvh_dir.{i}"
        folder = Path(item)
        if not folder.is_dir():
            raise VoxposeError(f"config key {key}: {folder} is not a folder")
        files = sorted(folder.glob("*.bvh"))
        if not files:
            raise VoxposeError(f"config key {key}: no .bvh files in {folder}")
        for f in files:
            if f.stem in out:
                raise VoxposeError(f"config key {key}: motion {f.stem!r} is in two folders: {out[f.stem]} and {f}")
            out[f.stem] = f
    return out


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
    """Training motions and named test sets of one experiment.

    ``exp["test"]`` is a list of patterns (one test set, named ``test``) or a mapping ``{set name: patterns}``.
    Returns ``{"train": [...], "test_sets": {name: [...]}, "test": every test motion once, in set order}``.
    A test motion also in training is refused, naming the motions.
    """
    key = f"{key_prefix}.{name}"
    exclude = set(match(exp.get("exclude", []), names, f"{key}.exclude", allow_empty=True))
    train = [m for m in match(exp["train"], names, f"{key}.train") if m not in exclude]
    if not train:
        raise VoxposeError(f"config key {key}.train: every training motion is excluded")
    named = isinstance(exp["test"], dict)
    test_sets = {}
    for set_name, patterns in (exp["test"] if named else {"test": exp["test"]}).items():
        set_key = f"{key}.test.{set_name}" if named else f"{key}.test"
        test = [m for m in match(patterns, names, set_key) if m not in exclude]
        if not test:
            raise VoxposeError(f"config key {set_key}: every test motion is excluded")
        overlap = sorted(set(train) & set(test))
        if overlap:
            raise VoxposeError(f"config key {set_key if named else key}: test motions also in training: "
                               f"{', '.join(overlap)}")  # fmt: skip
        test_sets[set_name] = test
    every_test = list(dict.fromkeys(m for motions in test_sets.values() for m in motions))
    return {"train": train, "test_sets": test_sets, "test": every_test}


def motion_set_tag(names) -> str:
    """Directory name of a set of motions by its content (``n<count>-<hash>``), so that experiments with the
    same training motions share one feature fit and one regressor, whatever the experiments are called."""
    digest = hashlib.sha256("\n".join(sorted(names)).encode()).hexdigest()[:10]
    return f"n{len(names)}-{digest}"


def _has_motions(patterns, names, exclude: set) -> bool:
    """Whether glob ``patterns`` (a list, or a mapping of lists) match a name not in ``exclude``."""
    if isinstance(patterns, dict):
        return any(_has_motions(p, names, exclude) for p in patterns.values())
    return bool(set(match(patterns, names, "", allow_empty=True)) - exclude)


def _matching_patterns(patterns, names):
    """``patterns`` (a list, or a mapping of lists) without the patterns that match no name."""
    if isinstance(patterns, dict):  # named test sets: a set none of whose patterns match is left out
        return {k: kept for k, p in patterns.items() if (kept := _matching_patterns(p, names))}
    return [p for p in patterns if fnmatch.filter(names, p)]


def resolve_experiments(experiments: dict, names, key_prefix: str, shipped: dict) -> tuple[dict, list]:
    """Resolved experiments by name (``resolve_experiment``), and the names of the shipped ones left out.

    An experiment exactly as the shipped config.yaml defines it (``shipped``: that file's section) names the
    motions of the data it was written for; on other data its patterns may match nothing, and when no training
    or no test motion is left it is left out (the workflow logs it) instead of stopping the run. Any other
    experiment is the user's own, and a pattern of it that matches nothing is an error as before.
    """
    names = sorted(names)
    out, skipped = {}, []
    for name, exp in experiments.items():
        if exp == shipped.get(name):
            exclude = set(match(exp.get("exclude", []), names, "", allow_empty=True))
            if not (_has_motions(exp["train"], names, exclude) and _has_motions(exp["test"], names, exclude)):
                skipped.append(name)
                continue
            exp = {k: _matching_patterns(v, names) for k, v in exp.items()}
        out[name] = resolve_experiment(name, exp, names, key_prefix)
    return out, skipped


def _lineage(name: str, sources: dict) -> list:
    """``name`` and the motions it was derived from (``sources``: derived motion -> its source), nearest first."""
    out = [name]
    while out[-1] in sources and sources[out[-1]] not in out:
        out.append(sources[out[-1]])
    return out


def resolve_generalisation(section: dict, names, key: str, sources: dict, shipped: dict) -> tuple[dict, list]:
    """Held-out-group experiments of a ``generalisation`` section, by group name, and the groups left out.

    The pool is the motions matching ``section["train"]``; a group is the pool motions that match its ``files``
    patterns, or whose source does (``sources``: derived motion -> source, so a derived walk follows its source's
    subject whatever its name). Holding a group out trains on the rest of the pool and tests on the group
    (``resolve_experiment``'s shape; the one test set is named after the group). A pool motion in no group is
    always trained on; one in two groups, a group with no motion and a group that leaves no training motion are
    errors naming the key. A section exactly as shipped (``shipped``) leaves those groups out instead.
    """
    lenient = section == shipped
    names = sorted(names)
    pool = match(section["train"], names, f"{key}.train", allow_empty=lenient)
    seen, out, skipped = {}, {}, []
    for i, group in enumerate(section["groups"]):
        name, gkey = group["name"], f"{key}.groups.{i}"
        if [g["name"] for g in section["groups"][:i]].count(name):
            raise VoxposeError(f"config key {gkey}.name: group {name!r} is named twice")
        members = [m for m in pool
                   if any(fnmatch.fnmatch(n, p) for n in _lineage(m, sources) for p in group["files"])]  # fmt: skip
        for m in members:
            if m in seen:
                raise VoxposeError(f"config key {gkey}.files: motion {m!r} is in two groups, {seen[m]} and {name}")
            seen[m] = name
        train = [m for m in pool if m not in members]
        if not (members and train):
            why = "matches no motion of the pool" if not members else "leaves no training motion when held out"
            if lenient:
                skipped.append(name)
                continue
            raise VoxposeError(f"config key {gkey}.files: group {name!r} {why} ({key}.train)")
        out[name] = {"train": train, "test_sets": {name: members}, "test": members}
    return out, skipped


def descriptor_tag(cfg: dict) -> str:
    """Readable directory name of a descriptor parameter set (Section 4)."""
    return DescriptorSettings.from_config(cfg).tag()


def feature_params(method: str, cfg: dict) -> dict:
    """The keys of the ``features`` section ``cfg`` that the ``method`` fit reads (``FIT_KEYS``; those present):
    a rule passes only these, so that a key of the other method (kmeans_neighbours; n_latent, tol) reruns
    nothing of this one."""
    if method not in FIT_KEYS:
        raise VoxposeError(f"unknown feature method {method!r} (mppca or kmeans)")
    return {k: cfg[k] for k in FIT_KEYS[method] if k in cfg}


def feature_tag(method: str, cfg: dict) -> str:
    """Readable directory name of a feature transformation (Section 5): MPPCA or the K-means baseline."""
    shape = "-shape" if cfg.get("heading_sense", "shape") == "shape" else ""  # the sense: the hull's own cue
    if method == "mppca":
        return f"mppca-K{cfg['n_components']}-q{cfg['n_latent']}{shape}"
    if method == "kmeans":
        return f"kmeans-K{cfg['n_components']}-n{cfg['kmeans_neighbours']}{shape}"
    raise VoxposeError(f"unknown feature method {method!r} (mppca or kmeans)")


# --- the measured claims (issue 8) ---------------------------------------------------------------------------

_RIG_OVERRIDES = ("n_cameras", "radius", "height", "target_height", "focal_px", "width", "image_height")


def rig_camera_count(section: dict) -> int:
    """Number of cameras of a `rig`-style section: its calibration file's, else ``n_cameras``."""
    if section.get("file"):
        from voxpose.voxels.cameras import load_rig

        return len(load_rig(section["file"]))
    return int(section["n_cameras"])


def check_rig_names(rigs: dict, rigs_dir) -> None:
    """Refuse a rig whose name already names another rig in ``rigs_dir`` (the workflow's ``results/rigs``).

    Every result carved from a rig lives under the rig's name, so a changed rig that kept its name would mix
    its results with the old rig's (and changing back would recompute them). ``rigs`` maps each rig name to
    (config key, config section): the default ``rig`` and the ``claims.rigs``.
    """
    from voxpose.voxels.cameras import rig_from_config, rig_json

    for name, (key, section) in rigs.items():
        path = Path(rigs_dir) / f"{name}.json"
        if path.is_file() and path.read_text() != rig_json(rig_from_config(section)):
            raise VoxposeError(
                f"config key {key}: the rig named {name!r} differs from the one in {path} that earlier results "
                f"were carved from; give the changed rig a new name (or delete {path} to replace it)"
            )


def claims_rigs(claims: dict, rig: dict) -> dict:
    """Test rigs of ``claims.rigs`` as complete `rig` sections (``name`` the entry's) by their results tag.

    A rig from a calibration ``file`` is tagged by its name. A rig that overrides some of the default ``rig``'s
    parameters depends on the default rig too, so its tag is ``<default rig name>.<name>``: a changed default
    rig must take a new name (``check_rig_names``), and the rigs derived from it then get new tags with it.
    Names must be unique, differ from the default rig's and not contain ``__`` (that marks degraded sets);
    ``claims.retrain`` may name only listed rigs.
    """
    out = {}
    names = set()
    for i, entry in enumerate(claims["rigs"]):
        name = entry["name"]
        if name == rig["name"] or name in names or "__" in name:
            why = "contains '__'" if "__" in name else "is used twice (or is the default rig's name)"
            raise VoxposeError(f"config key claims.rigs.{i}.name: {name!r} {why}")
        names.add(name)
        section = dict(rig, name=name, file=entry.get("file"))
        section |= {k: entry[k] for k in _RIG_OVERRIDES if k in entry}
        out[name if section["file"] else f"{rig['name']}.{name}"] = section
    if "__" in rig["name"]:
        raise VoxposeError(f"config key rig.name: {rig['name']!r} must not contain '__' (it marks degraded sets)")
    for i, name in enumerate(claims["retrain"]):
        if name not in names:
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
    radii = f"r{tag_number(cfg['r_inner'])}-{tag_number(cfg['r_outer'])}"
    return f"sc2d-p{cfg['n_points']}-{cfg['n_r']}x{cfg['n_theta']}-{radii}"


def at_tag(cfg: dict, cameras) -> str:
    """Readable name of an Agarwal & Triggs codebook on one camera (an index) or ``"all"`` cameras."""
    return f"at-K{cfg['n_centres']}-n{cfg['neighbours']}-" + ("all" if cameras == "all" else f"cam{cameras}")
