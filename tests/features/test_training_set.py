"""The training set read file by file (features/training_set.py) against the whole set in memory: the same
drawn rows, the same novelty frames, and a `fit-features` model equal to the one fitted on everything."""

import json

import numpy as np
import pytest

from voxpose.cli.main import main
from voxpose.descriptors.file import write_descriptors
from voxpose.features.model import FeatureModel, subsample
from voxpose.features.novelty import evenly_spaced
from voxpose.features.training_set import read_training_set

CFG = {"n_components": 3, "n_latent": 2, "max_iter": 20, "tol": 1e-6, "kmeans_neighbours": 2}


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """Four descriptor files of 8 bins: frames of 0-29 descriptors (some empty), one file with no rows at all;
    -> (paths, every frame in order, float64 as read)."""
    d = tmp_path_factory.mktemp("training_set")
    rng = np.random.default_rng(4)
    paths, frames = [], []
    for k, n_frames in enumerate([7, 3, 12, 5]):
        sizes = rng.integers(0, 30, size=n_frames) if k != 1 else np.zeros(n_frames, int)
        desc = [rng.gamma(2.0, size=(s, 8)) for s in sizes]
        path = d / f"m{k}.h5"
        write_descriptors(path, desc, [np.zeros((s, 3), np.int32) for s in sizes], {"motion": f"m{k}"})
        paths.append(path)
        frames.extend(d.astype(np.float32).astype(np.float64) for d in desc)  # as stored
    return paths, frames


@pytest.mark.parametrize("n", [None, 1, 17, 150, 10_000])
@pytest.mark.parametrize("n_frames", [1, 10, 500])
def test_the_same_rows_and_frames_as_the_whole_set(files, n, n_frames):
    paths, frames = files
    everything = np.concatenate([f for f in frames if len(f)])
    got = read_training_set(paths, n, seed=3, n_frames=n_frames)
    assert got.n_rows == len(everything) and got.n_frames == len(frames) == 27
    np.testing.assert_array_equal(got.rows, subsample(everything, n, 3))
    chosen = [frames[i] for i in evenly_spaced(len(frames), n_frames)]
    assert len(got.frames) == len(chosen)
    for a, b in zip(got.frames, chosen, strict=True):
        np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize("method", ["mppca", "kmeans"])
def test_fit_features_equals_the_fit_on_the_whole_set(files, tmp_path, method):
    paths, frames = files
    params = dict(CFG, fit_subsample=150)
    out = tmp_path / "model.h5"
    assert main(["fit-features", *map(str, paths), "--method", method, "--params", json.dumps(params),
                 "--seed", "5", "-o", str(out)]) == 0  # fmt: skip
    whole = np.concatenate([f for f in frames if len(f)])
    expected = FeatureModel.fit(method, whole, params, 5).with_novelty_range(frames)
    found = FeatureModel.load(out)
    (arrays, meta), (want_arrays, want_meta) = found.to_arrays(), expected.to_arrays()
    assert json.loads(json.dumps(meta)) == json.loads(json.dumps(want_meta))
    assert arrays.keys() == want_arrays.keys()
    for key, value in want_arrays.items():
        np.testing.assert_array_equal(arrays[key], value, err_msg=key)
    assert found.meta["n_train"] == len(whole) and found.meta["n_fit"] == 150
