"""The predicted-angles CSV, written without pandas, against pandas' own writer of the same table."""

import numpy as np
import pandas as pd

from voxpose.evaluation.angles_csv import write_angles
from voxpose.motion import canon


def _pandas_csv(predictions: dict) -> str:
    """The reference: the table pandas writes with the documented options."""
    frames = []
    for name, p in predictions.items():
        df = pd.DataFrame(p["pred_mvrvm"], columns=canon.ANGLE_NAMES)
        df.insert(0, "frame", range(len(df)))
        df.insert(0, "motion", name)
        frames.append(df)
    return pd.concat(frames).to_csv(index=False, float_format="%.4f")


def test_angles_csv_is_the_pandas_table(tmp_path):
    rng = np.random.default_rng(4)
    walk = rng.normal(scale=90.0, size=(5, len(canon.ANGLE_NAMES)))
    walk[1, 3] = np.nan  # a gap
    walk[2, 0] = -0.0
    walk[3, 5] = -0.00004  # rounds to -0.0000, as printf does
    walk[4, 7] = 12345.678951
    odd = rng.normal(size=(2, len(canon.ANGLE_NAMES)))
    predictions = {"walk_01": {"pred_mvrvm": walk}, 'odd, "quoted" name': {"pred_mvrvm": odd}}
    path = tmp_path / "predicted_angles.csv"
    write_angles(predictions, path)
    text = path.read_text()
    assert text == _pandas_csv(predictions)
    back = pd.read_csv(path)
    assert back.shape == (7, 2 + len(canon.ANGLE_NAMES)) and np.isnan(back.iloc[1, 2 + 3])
    np.testing.assert_allclose(back.iloc[:5, 2:].to_numpy(), walk, atol=5e-5)
