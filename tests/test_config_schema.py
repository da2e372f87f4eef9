"""The config schema's one validation: number-like strings read as numbers at numeric keys (PyYAML reads
``1e-3`` as text), other strings refused with the fix; every YAML example in config/README.md validates."""

import re

import pytest
import yaml

from tests.helpers import ROOT
from voxpose import workflow_config as wc
from voxpose.cli.main import main
from voxpose.config_schema import load_yaml, merge, section, validate
from voxpose.errors import VoxposeError


@pytest.fixture
def config():
    return yaml.safe_load((ROOT / "config" / "config.yaml").read_text())


_merge = merge  # Snakemake's --configfile semantics: nested dicts merge, other values replace


def test_pyyaml_reads_an_exponent_without_a_dot_as_text():
    assert yaml.safe_load("tol: 1e-3") == {"tol": "1e-3"}  # the premise of the leniency


@pytest.mark.parametrize(
    ("text", "key", "value"),
    [
        ("features: {tol: 1e-4}", ("features", "tol"), 1e-4),
        ("regression: {tol: 1E-3}", ("regression", "tol"), 1e-3),
        ("regression: {kernel_width: 2e1}", ("regression", "kernel_width"), 20.0),  # inside oneOf
        ("regression: {width_scales: [1e0, 5e-1]}", ("regression", "width_scales"), [1.0, 0.5]),
        ("descriptor: {r_min: '2'}", ("descriptor", "r_min"), 2),
        ("features: {n_components: 1e2}", ("features", "n_components"), 100),
    ],
)
def test_number_like_strings_are_read_as_numbers(config, text, key, value):
    config = _merge(config, yaml.safe_load(text))
    wc.validate_config(config)
    assert config[key[0]][key[1]] == value and not isinstance(config[key[0]][key[1]], str)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("features: {tol: small}", "config key features.tol: 'small' is not a number (a number is written like"),
        ("features: {n_components: '2.5'}", "config key features.n_components: 2.5 is not of type 'integer'"),
        ("features: {tol: -1e-3}", "config key features.tol: -0.001 is less than or equal to the minimum of 0"),
        ("features: {bogus: 1}", "config key features: unknown key 'bogus' (known: fit_subsample,"),
        ("motions: {unit_scale: nan}", "config key motions.unit_scale: "),
        ("features: {tol: 1e400}", "config key features.tol: '1e400' is not a number"),  # not infinity
    ],
)
def test_other_strings_and_keys_are_refused_naming_the_key(config, text, message):
    with pytest.raises(VoxposeError) as err:
        wc.validate_config(_merge(config, yaml.safe_load(text)))
    assert str(err.value).startswith(message), str(err.value)


def _readme_yaml_blocks():
    text = (ROOT / "config" / "README.md").read_text()
    return re.findall(r"```yaml\n(.*?)```", text, re.S)


@pytest.mark.parametrize("index", range(len(_readme_yaml_blocks())))
def test_every_yaml_example_in_the_config_readme_validates(config, index):
    block = yaml.safe_load(_readme_yaml_blocks()[index])
    wc.validate_config(_merge(config, block))


def test_the_config_readmes_defaults_validate_as_written(config):
    """The keys table writes numeric defaults like ``1e-4``: each, written as YAML under its key, validates."""
    text = (ROOT / "config" / "README.md").read_text()
    checked = []
    for keys, defaults in re.findall(r"^\| ((?:`[a-z_.]+`(?:, )?)+) \| ([^|]+) \|", text, re.M):
        keys = re.findall(r"`([a-z_.]+)`", keys)
        values = [v.split(" (")[0].strip() for v in defaults.split(",")]  # "0.333333333333 (1/3)"
        sect = keys[0].split(".")[0]
        for key, value in zip(keys, values, strict=False):
            name = key.split(".")[-1]
            current = config.get(sect, {}).get(name) if isinstance(config.get(sect), dict) else None
            if isinstance(current, int | float) and not isinstance(current, bool) and len(keys) == len(values):
                wc.validate_config(_merge(config, yaml.safe_load(f"{sect}: {{{name}: {value}}}")))
                checked.append(f"{sect}.{name}")
    assert {"features.tol", "regression.tol", "features.n_components"} <= set(checked), checked


def test_a_section_schema_checks_a_commands_parameters():
    schema = section("descriptor", required=False)
    validate({"n_r": 3}, schema, "--params")
    with pytest.raises(VoxposeError, match=r"^--params key n_r: 'abc' is not a number"):
        validate({"n_r": "abc"}, schema, "--params")
    with pytest.raises(VoxposeError, match=r"^--params: unknown key 'bogus' \(known: frame, n_a, n_e, n_r"):
        validate({"bogus": 1}, schema, "--params")
    with pytest.raises(VoxposeError, match=r"^--params: 'n_r' is a required property"):
        validate({}, section("descriptor"), "--params")


def test_broken_yaml_is_named_by_file_and_line(tmp_path):
    path = tmp_path / "my.yaml"
    path.write_text("seed: 1\nfeatures:\n  tol: [1.0\n  max_iter: 3\n")
    with pytest.raises(VoxposeError, match=rf"^{path}:4: not valid YAML: .*flow sequence \(from line 3\)"):
        load_yaml(path)
    path.write_text("seed: 1\n\tfeatures: 2\n")  # a tab
    with pytest.raises(VoxposeError, match=rf"^{path}:2: not valid YAML"):
        load_yaml(path)


@pytest.mark.parametrize(
    ("text", "error"),
    [
        ("features: {tol: 1e-3}\n", None),
        ("features:\n  tol: [1.0\n  max_iter: 3\n",
         "my.yaml:3: not valid YAML: while parsing a flow sequence (from line 2)"),
        ("features: {tol: abc}\n", "config key features.tol: 'abc' is not a number"),
        ("- 1\n", "my.yaml: expected a mapping"),
    ],
)
def test_check_config_names_what_snakemake_does_not(tmp_path, capsys, text, error):
    """Snakemake reads --configfile files itself and names neither file nor line of a YAML error."""
    (tmp_path / "my.yaml").write_text(text)
    status = main(["check-config", "--base", str(ROOT / "config" / "config.yaml"), str(ROOT / "config" / "quick.yaml"),
                   str(tmp_path / "my.yaml")])  # fmt: skip
    err = capsys.readouterr().err
    if error is None:
        assert status == 0
    else:
        assert status == 2 and err.strip().splitlines()[-1].startswith("voxpose: error: ") and error in err, err
