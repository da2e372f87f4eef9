"""PNG silhouette folders: round trip to identical voxels, mask rules, and every layout error."""

import numpy as np
import pytest
from PIL import Image

from tests.helpers import walk_motion
from voxpose.errors import VoxposeError
from voxpose.voxels.body import body_ellipsoids
from voxpose.voxels.cameras import circular_rig
from voxpose.voxels.carve import Carver
from voxpose.voxels.render import render_silhouettes
from voxpose.voxels.silhouettes import (
    iter_silhouette_folder,
    read_mask,
    silhouette_frame_numbers,
    write_silhouette_folder,
)

RIG = circular_rig(n=4, width=200, image_height=160, focal_px=230.0)


@pytest.fixture(scope="module")
def frames():
    motion = walk_motion(2)
    el = body_ellipsoids(motion).translated(-motion.positions[:, 0] * [1, 0, 1])
    return np.stack([render_silhouettes(el.frame(f), RIG) for f in range(2)])


def read_folder(directory, rig):
    """Every frame of a silhouette folder, (F, C, H, W) bool."""
    return np.stack(list(iter_silhouette_folder(directory, rig)))


@pytest.fixture
def folder(tmp_path, frames):
    assert write_silhouette_folder(frames, RIG, tmp_path / "sil") == 2
    return tmp_path / "sil"


def test_round_trip_carves_the_same_voxels(folder, frames):
    assert sorted(p.name for p in folder.iterdir()) == ["cam0", "cam1", "cam2", "cam3"]
    assert sorted(p.name for p in (folder / "cam2").iterdir()) == ["000000.png", "000001.png"]
    back = read_folder(folder, RIG)
    assert back.dtype == bool and np.array_equal(back, frames)
    carver = Carver(RIG, 0.03)
    for f in range(2):
        direct = carver(frames[f])
        assert len(direct) > 500 and np.array_equal(carver(back[f]), direct)
    assert silhouette_frame_numbers(folder, RIG) == [0, 1]
    assert not list(folder.rglob(".*"))  # no temporary files left behind


def test_frame_numbers_may_start_anywhere(tmp_path, frames):
    write_silhouette_folder(iter(frames), RIG, tmp_path / "s", first_frame=41)
    assert silhouette_frame_numbers(tmp_path / "s", RIG) == [41, 42]
    assert np.array_equal(np.stack(list(iter_silhouette_folder(tmp_path / "s", RIG))), frames)


@pytest.mark.parametrize(
    "pixels, expected",
    [
        (np.array([[0, 255], [255, 0]], np.uint8), [[False, True], [True, False]]),
        (np.array([[3, 1], [1, 1]], np.uint8), [[True, False], [False, False]]),  # 0/1-style masks
        (np.zeros((2, 2), np.uint8), [[False, False], [False, False]]),
        (np.full((2, 2), 200, np.uint8), [[True, True], [True, True]]),
        (np.array([[0, 65535], [0, 0]], np.uint16), [[False, True], [False, False]]),
    ],
)
def test_mask_threshold_rule(tmp_path, pixels, expected):
    path = tmp_path / "m.png"
    Image.fromarray(pixels).save(path)
    assert read_mask(path, 2, 2).tolist() == expected


def test_colour_masks_are_read_as_grey(tmp_path):
    rgb = np.zeros((2, 3, 3), np.uint8)
    rgb[0, 1] = 255
    Image.fromarray(rgb).save(tmp_path / "c.png")
    assert read_mask(tmp_path / "c.png", 3, 2).tolist() == [[False, True, False], [False, False, False]]


def test_grey_masks_are_thresholded_at_half_range(folder):
    soft = np.zeros((160, 200), np.uint8)
    soft[:, :50] = 127  # an anti-aliased edge, say: just below half
    soft[:, 50:60] = 128  # just at half
    soft[:, 100:] = 255
    Image.fromarray(soft).save(folder / "cam1" / "000001.png")
    mask = read_folder(folder, RIG)[1, 1]
    assert not mask[:, :50].any() and mask[:, 50:60].all() and not mask[:, 60:100].any() and mask[:, 100:].all()
    Image.fromarray(soft.astype(np.uint16) * 257).save(folder / "cam2" / "000001.png")  # 16-bit: 32767 vs 32896
    assert np.array_equal(read_folder(folder, RIG)[1, 2], mask)


def test_layout_by_pattern_keeps_frame_numbers_and_takes_the_rigs_cameras(folder, tmp_path):
    from voxpose.voxels.silhouettes import silhouette_frame_numbers

    expected = read_folder(folder, RIG)
    flat = tmp_path / "flat"
    flat.mkdir()
    for path in folder.glob("cam*/*.png"):
        (flat / f"view_{path.parent.name}_f{int(path.stem) + 40}.png").write_bytes(path.read_bytes())
    (flat / "view_cam9_f40.png").write_bytes(path.read_bytes())  # a camera the rig does not use
    pattern = "view_{camera}_f{frame}.png"
    assert silhouette_frame_numbers(flat, RIG, pattern) == [40, 41]
    assert np.array_equal(np.stack(list(iter_silhouette_folder(flat, RIG, pattern))), expected)
    with pytest.raises(VoxposeError, match="needs \\{frame\\} exactly once"):
        silhouette_frame_numbers(flat, RIG, "view_{camera}.png")


def test_wrong_image_size(folder):
    Image.fromarray(np.zeros((160, 199), np.uint8)).save(folder / "cam3" / "000000.png")
    with pytest.raises(VoxposeError, match=r"cam3/000000.png: image is 199x160, the camera's is 200x160"):
        read_folder(folder, RIG)


def test_folders_not_matching_the_rig(folder):
    (folder / "cam2").rename(folder / "side")
    with pytest.raises(VoxposeError, match="no frames for camera\\(s\\) cam2"):
        read_folder(folder, RIG)
    (folder / "side").rename(folder / "cam2")
    (folder / "extra").mkdir()  # a camera the rig does not use: ignored
    (folder / "extra" / "000000.png").write_bytes((folder / "cam0" / "000000.png").read_bytes())
    (folder / ".cache").mkdir()  # hidden entries are ignored
    assert read_folder(folder, RIG).shape == (2, 4, 160, 200)


def test_differing_frame_counts_and_stray_files(folder, tmp_path):
    (folder / "cam3" / "000001.png").unlink()
    with pytest.raises(VoxposeError, match="cam3: 1 frames, .*cam0 has 2 \\(frame 1 is in one folder only\\)"):
        read_folder(folder, RIG)
    (folder / "cam3" / "notes.txt").write_text("x")
    with pytest.raises(VoxposeError, match="notes.txt: not a silhouette frame"):
        read_folder(folder, RIG)
    with pytest.raises(VoxposeError, match="silhouette folder not found"):
        read_folder(tmp_path / "nowhere", RIG)


def test_write_rejects_wrong_frames(tmp_path, frames):
    with pytest.raises(VoxposeError, match="frame 0 is uint8"):
        write_silhouette_folder(frames.astype(np.uint8), RIG, tmp_path / "x")
    with pytest.raises(VoxposeError, match=r"frame 1 is bool \(3, 160, 200\)"):
        write_silhouette_folder([frames[0], frames[1][:3]], RIG, tmp_path / "y")
