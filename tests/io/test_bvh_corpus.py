"""The malformed-BVH corpus (tests/io/bvh_corpus.py) through the reader, the header reader the workflow sizes
its jobs with, and the command: every malformed file refused with one line naming it, the header reader's
message and line the same as the full reader's, the well-formed variants loaded."""

import pytest

from tests.io.bvh_corpus import N_FRAMES, corpus, write_corpus
from voxpose.cli.main import main
from voxpose.errors import VoxposeError
from voxpose.io.bvh import read_bvh, read_duration


@pytest.fixture(scope="module")
def cases(tmp_path_factory):
    paths = write_corpus(tmp_path_factory.mktemp("corpus"))
    return {c.name: (c, paths[c.name]) for c in corpus()}


MALFORMED = [c.name for c in corpus() if c.part]


def _message(path, read) -> str:
    with pytest.raises(VoxposeError) as err:
        read(path)
    return str(err.value)


def test_the_corpus_holds_19_malformed_files():
    assert len(MALFORMED) == 19


@pytest.mark.parametrize("name", MALFORMED)
def test_a_malformed_file_is_refused_naming_file_and_line(cases, name):
    case, path = cases[name]
    text = _message(path, read_bvh)
    prefix = f"{path}:{case.line}: " if case.line else f"{path}: "
    assert text.startswith(prefix) and case.fragment in text, text
    assert "\n" not in text and ":0:" not in text


@pytest.mark.parametrize("name", MALFORMED)
def test_the_header_reader_agrees_with_the_full_reader(cases, name):
    case, path = cases[name]
    if case.part == "header":
        assert _message(path, read_duration) == _message(path, read_bvh)
    else:  # an error in the frame lines is found when the motion is loaded
        assert read_duration(path)[0] >= N_FRAMES - 2


@pytest.mark.parametrize("name", ["crlf", "utf8_bom"])
def test_well_formed_variants_load_as_the_original(cases, tmp_path, name):
    _, path = cases[name]
    original = read_bvh(path.with_name("walk_crlf.bvh"))  # same text
    bvh = read_bvh(path)
    assert [j.name for j in bvh.joints][0] == "Hips" and (bvh.motion == original.motion).all()
    assert read_duration(path) == (N_FRAMES, bvh.frame_time)


def test_other_encodings_are_named(tmp_path):
    text = "HIERARCHY\nROOT Hips\n"
    for encoding, name in (("utf-16-le", "UTF-16 (little-endian) without a byte-order mark"),
                           ("utf-16-be", "UTF-16 (big-endian) without a byte-order mark"),
                           ("utf-32", "UTF-32 (little-endian)"), ("utf-16", "UTF-16 (little-endian)")):  # fmt: skip
        path = tmp_path / f"{encoding}.bvh"
        path.write_bytes(text.encode(encoding))
        assert _message(path, read_bvh).startswith(f"{path}: the file is {name} text"), encoding
    latin = tmp_path / "latin1.bvh"
    latin.write_bytes("HIERARCHY\nROOT Hüfte\n".encode("latin-1"))
    assert _message(latin, read_duration).startswith(f"{latin}:2: byte 0xfc is not UTF-8")


@pytest.mark.parametrize("command", ["motion", "turn"])
@pytest.mark.parametrize("name", [*MALFORMED, "crlf"])
def test_the_command_refuses_each_malformed_file_in_one_line(cases, tmp_path, capsys, command, name):
    case, path = cases[name]
    if command == "motion":
        out = tmp_path / f"{path.stem}.h5"
        argv = ["motion", str(path), "-o", str(out)]
    else:
        out = tmp_path / f"{path.stem}_turn090.bvh"
        argv = ["derive", str(path), "--kind", "turn", "--params", '{"degrees": 90}', "--seed", "0", "-o", str(out)]
    status = main(argv)
    err = capsys.readouterr().err
    if not case.part:
        assert status == 0 and out.exists()
        return
    expected = _message(path, read_bvh)
    assert status == 2
    assert [line for line in err.splitlines() if "error" in line] == [f"voxpose: error: {expected}"]
    assert not out.exists() and list(tmp_path.iterdir()) == []
