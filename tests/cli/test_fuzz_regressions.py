"""Inputs the fuzz tests found that ended in an internal error, each now a located
error (or, for an empty template, a valid empty model). Every case runs the real
command and checks the exact message the user gets."""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from support.cli_outcome import assert_clean, assert_clean_outcome, run

ROOT = Path(__file__).resolve().parents[2]
MAPPING = ROOT / "product_lines" / "mapping3d"
DATA = ROOT / "product_lines" / "data_acquisition"
FLEET = ROOT / "tests" / "models" / "launch"


def copy_line(source: Path, tmp_path: Path) -> Path:
    copy = tmp_path / source.name
    shutil.copytree(source, copy)
    return copy


def errors(result) -> list[str]:
    return [line for line in result.stderr.splitlines() if ": error: " in line]


def test_an_empty_template_is_an_empty_model(tmp_path):
    # was: internal error: AttributeError: 'str' object has no attribute 'name'
    # (fleet.tsm mutated to '': textX gives '' for a file with no element)
    for text in ("", "   \n// only a comment\n"):
        path = tmp_path / "empty.tsm"
        path.write_text(text, encoding="utf-8")
        result = run("check", path)
        assert_clean(result, repr(text))
        assert result.exit_code == 0
        assert "ok: 0 containers, 0 nodes, 0 topics, 0 interfaces, 0 bridges" in result.stdout


def test_an_emptied_template_of_a_line_is_reported_through_the_line(tmp_path):
    line = copy_line(FLEET, tmp_path)
    (line / "fleet.tsm").write_text("", encoding="utf-8")
    result = run("check", line)
    assert_clean(result, "fleet.tsm emptied")
    assert result.exit_code == 1
    assert any("fleet.rm" in e and "unknown" in e for e in errors(result))


@pytest.mark.parametrize(
    ("text", "where", "character"),
    [
        # was: internal error: ReaderError: unacceptable character #x001e
        ("features: [Ë÷Â\U0003fb7f\x1e]\n", "1:16", "U+001E"),
        (" : misspelt\nfeatures:product[\x7f <- ]\nsharng: {Fast: private}", "2:18", "U+007F"),
    ],
)
def test_a_control_character_in_a_selection_is_located(tmp_path, text, where, character):
    selection = tmp_path / "p.yaml"
    selection.write_text(text, encoding="utf-8")
    out = tmp_path / "out"
    out.mkdir()
    result = run("resolve", MAPPING, "--features", selection, "-o", out / "bundle")
    assert_clean(result, repr(text), out)
    assert errors(result) == [
        f"{selection}:{where}: error: invalid YAML: character {character} is not allowed"
    ]


@pytest.mark.parametrize(
    ("text", "message"),
    [
        # each was an internal error (TypeError, ValueError, ConstructorError)
        ("sharing: {[x]: private}", "2:11: error: sharing: expected a name, got a list"),
        ("attributes: {[a]: 1}", "2:14: error: attributes: expected a name, got a list"),
        ("deployment: {[R]: {}}", "2:14: error: deployment: a list is not a container name"),
        (
            "deployment: {Robot: {[R]: x}}",
            "2:22: error: deployment: Robot: expected a name, got a list",
        ),
        (
            "attributes: {Logging.rate: !foo 1}",
            "2:28: error: attributes: Logging.rate: invalid YAML value: could not determine a "
            "constructor for the tag '!foo'",
        ),
        (
            "attributes: {Logging.rate: !!float x}",
            "2:28: error: attributes: Logging.rate: invalid YAML value: could not convert "
            "string to float: 'x'",
        ),
        ("attributes: {Logging.rate: " + "[" * 600 + "]" * 600 + "}", "1:1: error: invalid "),
    ],
)
def test_odd_yaml_in_a_selection_is_located(tmp_path, text, message):
    selection = tmp_path / "p.yaml"
    selection.write_text(f"features: [YouBot]\n{text}\n", encoding="utf-8")
    result = run("resolve", MAPPING, "--features", selection, "-o", tmp_path / "out")
    assert_clean(result, text)
    assert result.exit_code == 1
    assert any(e.startswith(f"{selection}:{message}") for e in errors(result)), result.stderr


@pytest.mark.parametrize(
    ("setting", "message"),
    [
        ("FastRefresh.period=[", "attribute FastRefresh.period is double, got '['"),
        ("FastRefresh.period=!!float x", "attribute FastRefresh.period is double, got '!!float x'"),
        # were: ValueError / OverflowError deep in the generators
        ("FastRefresh.period=.nan", "attribute FastRefresh.period is double, got '.nan'"),
        ("FastRefresh.period=inf", "attribute FastRefresh.period is double, got 'inf'"),
        ("FastRefresh.period=-1e999", "attribute FastRefresh.period is double, got -inf"),
    ],
)
def test_odd_attribute_values_are_refused(tmp_path, setting, message):
    product = DATA / "products" / "both_fast_refresh.yaml"
    out = tmp_path / "out"
    out.mkdir()
    result = run("resolve", DATA, "--features", product, "--set", setting, "-o", out / "b")
    assert_clean(result, setting, out)
    assert result.exit_code == 1
    assert any(e.startswith("--set:1:1: error: ") and message in e for e in errors(result))


DIGITS = "9" * 5000  # past Python's 4300-digit limit for int(str)


@pytest.mark.parametrize(
    ("name", "text", "message"),
    [
        (
            "a.fm",
            f"feature model X\nroot R {{ attribute a : int = {DIGITS} }}\n",
            f"2:30: error: attribute a: {DIGITS} is not an int",
        ),
        (
            "b.fm",
            f"feature model X\nroot R {{ group [{DIGITS}..*] {{ A B }} }}\n",
            "2:10: error: bad cardinality: a bound is out of range (at most 2147483647)",
        ),
        (
            "c.tsm",
            f"cloud container C size {DIGITS} {{ }}\n",
            f"1:24: error: size {DIGITS} is out of range (at most 2147483647)",
        ),
        (
            "d.tsm",
            f"data D {{ x : double }}\ntransform T : D -> D {{ x = x + {DIGITS} }}\n",
            f"2:32: error: number {DIGITS} is out of range",
        ),
        (
            "e.tsm",
            f"cloud container C {{ node N {{ param p : int = {DIGITS} }} }}\n",
            f"1:46: error: parameter p is int: {DIGITS} is out of range",
        ),
        (
            "f.tsm",
            'cloud container C { node N { param p : yaml = "!!float x" } }\n',
            "1:47: error: parameter p is yaml: invalid YAML: could not convert string to float",
        ),
    ],
)
def test_huge_numbers_and_unconvertible_yaml_in_models_are_located(tmp_path, name, text, message):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    result = run("check", path)
    assert_clean(result, text[:80])
    assert result.exit_code == 1
    assert any(e.startswith(f"{path}:{message}") for e in errors(result)), result.stderr


@pytest.mark.parametrize(
    "expression",
    ["(" * 3000 + "x" + ")" * 3000, "-" * 3000 + "x", "+".join(["x"] * 600)],
    ids=["parentheses", "negations", "long-sum"],
)
def test_a_transform_nested_too_deeply_is_located(tmp_path, expression):
    # was: internal error: RecursionError: maximum recursion depth exceeded
    path = tmp_path / "deep.tsm"
    path.write_text(
        f"data D {{ x : double }}\ntransform T : D -> D {{\n x = {expression}\n}}\n",
        encoding="utf-8",
    )
    result = run("check", path)
    assert_clean(result, expression[:40])
    # at the outermost parenthesis of the deepest nesting, else the longest line's start
    col = 6 if expression.startswith("(") else 1
    assert errors(result) == [
        f"{path}:3:{col}: error: a transform expression is nested too deeply or too long"
    ]


@pytest.mark.parametrize("model", ["mapping.rm", "mapping.fm", "products/roomba_depth_room.yaml"])
def test_a_file_that_is_not_utf8_is_located(tmp_path, model):
    # was: internal error: UnicodeDecodeError (the .tsm already said so plainly)
    line = copy_line(MAPPING, tmp_path)
    path = line / model
    data = path.read_bytes() + b"\n// \xff\n"
    path.write_bytes(data)
    row, col = data.count(b"\n", 0, len(data) - 2) + 1, 4
    features = str(path) if model.endswith(".yaml") else "YouBot,Depth,Room"
    out = tmp_path / "out"
    out.mkdir()
    result = run("resolve", line, "--features", features, "-o", out / "bundle")
    assert_clean(result, model, out)
    assert errors(result) == [
        f"{path}:{row}:{col}: error: file is not UTF-8 text (invalid start byte)"
    ]


@pytest.mark.parametrize(
    ("value", "message"),
    [
        ("1e999", "parameter rate is double: 1e999 is out of range"),
        (
            DIGITS,
            f"parameter port is int: {DIGITS} is out of range: ROS 1 parameters are 32-bit "
            "integers, at most 2147483647 in magnitude",
        ),
    ],
)
def test_rm_parameter_values_out_of_range_are_refused(tmp_path, value, message):
    # 1e999 used to become the double `inf` in the launch files; a 5000-digit int crashed
    line = tmp_path / "line"
    line.mkdir()
    (line / "l.fm").write_text("feature model L\nroot R { optional F }\n", encoding="utf-8")
    (line / "l.tsm").write_text(
        "cloud container C { node N { param rate : double = 1.0\n param port : int = 1 } }\n",
        encoding="utf-8",
    )
    parameter = "rate" if value == "1e999" else "port"
    (line / "l.rm").write_text(
        f'resolution model L\ntsm "l.tsm"\nfm "l.fm"\n'
        f"when F selected {{ parameter N.{parameter} = {value} }}\n",
        encoding="utf-8",
    )
    result = run("check", line / "l.rm")
    assert_clean(result, value[:20])
    assert errors(result) == [f"{line / 'l.rm'}:4:19: error: {message}"]


def test_a_uvl_cardinality_of_thousands_of_digits_is_located(tmp_path):
    # was: internal error: ValueError: Exceeds the limit (4300 digits)
    path = tmp_path / "big.uvl"
    path.write_text(f"features\n\tR\n\t\t[1..{DIGITS}]\n\t\t\tA\n\t\t\tB\n", encoding="utf-8")
    result = run("analyze", path)
    assert_clean(result, "uvl cardinality")
    assert errors(result) == [
        f"{path}:3:3: error: bad cardinality [1..{DIGITS}]: a bound is out of range"
    ]


def test_validate_reads_a_listed_product_whose_name_does_not_convert(tmp_path):
    # was: internal error: ValueError while reading the product's name for the report
    line = copy_line(MAPPING, tmp_path)
    listed = line / "products" / "odd.yaml"
    listed.write_text("product: !!float x\nfeatures: [YouBot, Depth, Room]\n", encoding="utf-8")
    result = run("validate", line)
    assert_clean(result, "validate")
    assert "ok   mapping3d :: odd" in result.stdout  # the file's name stands in for it


@pytest.mark.parametrize(
    ("name", "text", "code"),
    [
        ("empty.tsm", "", 0),
        ("odd.fm", f"feature model X\nroot R {{ group [{DIGITS}..*] {{ A B }} }}\n", 1),
        (
            "deep.tsm",
            "data D { x : double }\ntransform T : D -> D { x = " + "-" * 3000 + "x }\n",
            1,
        ),
        ("bytes.rm", "resolution model \udcff\n", 1),
    ],
)
def test_the_installed_command_exits_plainly_on_fuzzed_input(tmp_path, name, text, code):
    """The same inputs through the real process entry point (exit status, stderr)."""
    path = tmp_path / name
    path.write_text(text, encoding="utf-8", errors="surrogateescape")
    done = subprocess.run(
        [sys.executable, "-m", "spl", "check", str(path)],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert_clean_outcome(done.returncode, done.stdout, done.stderr, name)
    assert done.returncode == code


@pytest.mark.parametrize(
    ("value", "message"),
    [
        (
            "99999999999999999999999",
            "2:7: error: attribute a: 99999999999999999999999 is out of range",
        ),
        # UVL's grammar has no exponent: the reader stops at it, as the reference parser does
        ("1e999", "2:8: error: expected ',' or '}' in the attribute list, got e999"),
    ],
)
def test_a_uvl_attribute_out_of_range_is_located_not_dropped(tmp_path, value, message):
    # was: imported with no value, and `spl convert` wrote `attribute a : int = `, an
    # .fm that does not parse (the int case since the 64-bit bound, the double one always)
    source = tmp_path / "big.uvl"
    source.write_text(f"features\n\tR {{a {value}}}\n\t\toptional\n\t\t\tA\n", encoding="utf-8")
    target = tmp_path / "big.fm"
    result = run("convert", source, target)
    assert_clean(result, value)
    assert errors(result) == [f"{source}:{message}"]
    assert not target.exists()


def test_int_parameters_fit_ros1s_32_bit_parameter_server(tmp_path):
    """3000000000 passed spl check and spl validate, then roslaunch failed on the robot
    ("int exceeds XML-RPC limits"). A .tsm or .rm literal beyond 32 bits is refused by
    spl check, an attribute value beyond them by spl resolve, each at its location; the
    largest 32-bit value still resolves into both launch files."""
    line = tmp_path / "line"
    line.mkdir()
    (line / "l.fm").write_text(
        "feature model L\nroot R { optional F { attribute limit : int = 2147483647 } }\n",
        encoding="utf-8",
    )
    tsm = line / "l.tsm"
    tsm.write_text(
        "cloud container Bot {\n node N { implementation p/n\n param p : int = 1 } }\n",
        encoding="utf-8",
    )
    rm = line / "l.rm"
    rm.write_text(
        'resolution model L\ntsm "l.tsm"\nfm "l.fm"\n'
        "when F selected { parameter N.p = feature F.limit }\n",
        encoding="utf-8",
    )
    out = tmp_path / "out"
    assert run("resolve", line, "--features", "R,F", "-o", out).exit_code == 0
    for launch in ("ros1/Bot.launch", "ros2/Bot.launch.xml"):
        assert 'value="2147483647"' in (out / launch).read_text()
    range_text = "ROS 1 parameters are 32-bit integers, at most 2147483647 in magnitude"

    result = run("resolve", line, "--features", "R,F", "--set", "F.limit=-2147483648", "-o", out)
    assert result.exit_code == 1
    assert errors(result) == [
        f"{rm}:4:19: error: parameter N.p cannot be feature attribute F.limit = -2147483648: "
        + range_text
    ]
    assert 'value="2147483647"' in (out / "ros1/Bot.launch").read_text()  # left as it was

    tsm.write_text(tsm.read_text().replace("= 1 }", "= 2147483648 }"), encoding="utf-8")
    result = run("check", line)
    assert result.exit_code == 1
    assert f"{tsm}:3:18: error: parameter p is int: 2147483648 is out of range: " in result.output

    tsm.write_text(tsm.read_text().replace("2147483648", "1"), encoding="utf-8")
    rm.write_text(rm.read_text().replace("feature F.limit", "-3000000000"), encoding="utf-8")
    result = run("check", line)
    assert result.exit_code == 1
    assert f"{rm}:4:19: error: parameter p is int: -3000000000 is out of range: " in result.output


@pytest.mark.parametrize(
    ("name", "text", "message"),
    [
        ("empty.fm", "", "1:1: error: syntax error: expected 'feature'"),
        ("comment.fm", "// only a comment\n", "2:1: error: syntax error: expected 'feature'"),
        ("empty.rm", "", "1:1: error: syntax error: expected resolution"),
        ("node.tsm", "cloud container C { node }\n", "1:26: error: syntax error: expected a name"),
    ],
)
def test_syntax_errors_do_not_list_the_comment_pattern(tmp_path, name, text, message):
    # was: "expected '\/\/[^\n]*' or 'feature'": the grammars' comment regex shown to users
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    result = run("check", path)
    assert result.exit_code == 1
    assert errors(result)[0].startswith(f"{path}:{message}")
    assert "\\/" not in result.output


@pytest.mark.parametrize(
    ("value", "where"),
    [("null", ""), ("{}", ""), ("{b: ~}", " (at b)"), ("{a: {c: {}}}", " (at a.c)")],
)
def test_yaml_parameters_ros2_cannot_hold_are_located(tmp_path, value, where):
    # were: check 0 errors, then resolve "internal error: ValueError: parameter Cam.y:
    # ROS 2 parameters cannot be null or empty" (exit 3) in every product
    path = tmp_path / "y.tsm"
    path.write_text(
        f'cloud container C {{ node N {{ implementation p/n\n param y : yaml = "{value}" }} }}\n',
        encoding="utf-8",
    )
    result = run("check", path)
    assert result.exit_code == 1
    assert errors(result) == [
        f"{path}:2:19: error: parameter y is yaml: ROS 2 parameters cannot be null or empty{where}"
    ]


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (  # was: resolve "internal error: BundlePathClash: ros1/cloud.launch and ros1/Cloud.launch"
            "cloud container cloud { }\ncloud container Cloud { }\n",
            "2:17: error: container name Cloud differs from cloud (line 1) only in case",
        ),
        (  # was: the generated service failed to start, "duplicate column name: Lat"
            "data In { lat : double\n Lat : int }\n",
            "2:2: error: data In: fields lat and Lat would be one database column",
        ),
        (  # was accepted; "duplicate column name: ID" at service start
            "data In { ID : int }\n",
            "1:11: error: data In: field name 'ID' is reserved",
        ),
        (  # PostgreSQL keeps 63 characters: "specified more than once"
            f"data In {{ {'a' * 63}x : int\n {'a' * 63}y : int }}\n",
            f"2:2: error: data In: fields {'a' * 63}x and {'a' * 63}y would be one database column",
        ),
    ],
)
def test_names_one_file_or_column_apart_only_in_case_are_located(tmp_path, text, message):
    path = tmp_path / "m.tsm"
    path.write_text(text, encoding="utf-8")
    result = run("check", path)
    assert result.exit_code == 1
    assert errors(result)[0].startswith(f"{path}:{message}"), errors(result)


def two_robot_line(tmp_path, *robot_ids: str):
    """A line of robot containers R0, R1, ... with these robot_ids and one feature R."""
    line = tmp_path / "line"
    line.mkdir()
    robots = "".join(
        f'robot container R{i} {{ endpoint robot_id "{rid}" url "wss://c.example.org:9000/" '
        f'user "u" password env "P"\n node N{i} {{ implementation p/n }} }}\n'
        for i, rid in enumerate(robot_ids)
    )
    (line / "l.tsm").write_text(robots, encoding="utf-8")
    (line / "l.fm").write_text("feature model L\nroot R\n", encoding="utf-8")
    (line / "l.rm").write_text('resolution model L\ntsm "l.tsm"\nfm "l.fm"\n', encoding="utf-8")
    return line


def test_robot_ids_apart_only_in_case_are_located(tmp_path):
    # was: resolve "internal error: BundlePathClash: zenoh/ROBOT_1.json5 and zenoh/robot_1.json5"
    line = two_robot_line(tmp_path, "robot_1", "ROBOT_1")
    out = tmp_path / "out"
    result = run("resolve", line, "--features", "R", "-o", out)
    assert result.exit_code == 1 and not out.exists()
    assert errors(result) == [
        f"{line / 'l.tsm'}:3:17: error: Rapyuta tags 'robot_1' (robot container R0) and "
        "'ROBOT_1' (robot container R1) differ only in case: their bundle files would be one "
        "file on a case-insensitive file system; rename one"
    ]


def test_smoke_reads_a_bundles_resolved_tsm_as_spl_check_does(tmp_path):
    # were: a Latin-1 byte "internal error: UnicodeDecodeError" (exit 3); a byte order
    # mark, which spl check drops, a syntax error under spl smoke
    from spl.pipeline import read_bundle

    bundle = tmp_path / "bundle"
    assert run("resolve", MAPPING, "--features", "YouBot,Depth,Room", "-o", bundle).exit_code == 0
    model = bundle / "resolved.tsm"
    text = model.read_bytes()
    model.write_bytes(b"\xef\xbb\xbf" + text)
    assert read_bundle(bundle)[1] == "YouBot_Depth_Room"
    model.write_bytes(b"system S \xe9\n")
    result = run("smoke", bundle)
    assert result.exit_code == 1
    assert errors(result) == [
        f"{model}:1:10: error: file is not UTF-8 text (invalid continuation byte)"
    ]


def test_smoke_refuses_a_fleet_bundle_saying_why(tmp_path):
    # was: 23 failures, "ros1/MappingCloud.launch is not a launch file name", on the
    # fleet's robot folders; "no resolved.tsm" on the fleet folder
    fleet = tmp_path / "lab"
    assert run("fleet", "resolve", MAPPING / "fleets" / "lab.yaml", "-o", fleet).exit_code == 0
    for bundle, what in [(fleet, "a fleet bundle"), (fleet / "robots" / "youbot_1", "part of a")]:
        result = run("smoke", bundle)
        assert result.exit_code == 1
        assert result.stderr.splitlines() == [
            f"error: {bundle} is {what}{'' if what.endswith('bundle') else ' fleet bundle'} "
            "(spl fleet resolve): spl smoke rehearses one product's bundle as spl resolve "
            "writes it; resolve the robot's product with spl resolve to rehearse it"
        ]


@pytest.mark.parametrize("name", ["Lögger", "1e3"])
def test_rm_syntax_errors_name_what_a_name_is_not_its_pattern(tmp_path, name):
    # was: "expected [A-Za-z_][A-Za-z0-9_]*(?![^\x00-\x7f])"
    line = copy_line(MAPPING, tmp_path)
    rm = line / "mapping.rm"
    rm.write_text(rm.read_text() + f"when Stereo selected {{ migrate {name} to Robot }}\n")
    result = run("check", rm)
    assert result.exit_code == 1
    (message,) = errors(result)
    assert message.endswith(
        "syntax error: expected a name (ASCII letters, digits and '_', not starting with a digit)"
    )


def test_a_missing_model_is_located_at_its_header_line(tmp_path):
    # was: at 1:1 (the `resolution model` line) whichever line named the file
    line = copy_line(MAPPING, tmp_path)
    rm = line / "mapping.rm"
    text = rm.read_text()
    rm.write_text(re.sub(r'fm\s+"mapping.fm"', '// fm "old.fm"\nfm "nope.uvl"', text))
    row = rm.read_text().splitlines().index('fm "nope.uvl"') + 1
    result = run("check", rm)
    assert result.exit_code == 1
    assert errors(result) == [f"{rm}:{row}:1: error: fm file '{line / 'nope.uvl'}' not found"]


def test_old_mac_line_ends_count_as_lines(tmp_path):
    # was: every position on line 1 ("s.tsm:1:466"): the parsers count only line feeds
    path = tmp_path / "cr.tsm"
    text = "system S\rcloud container C {\r node N { implementation p/n }\r node N { } }\r"
    path.write_bytes(text.encode())
    result = run("check", path)
    assert errors(result) == [
        f"{path}:4:7: error: duplicate node name N in container C (first declared at line 3)"
    ]
    path.write_bytes(text.replace("\r", "\r\n").encode())  # Windows line ends, as before
    assert errors(run("check", path)) == errors(result)


@pytest.mark.parametrize("value", ["0", "-5", "1e9", "5e-324", "0.0005"])
def test_a_period_attribute_out_of_range_is_located_where_it_is_used(tmp_path, value):
    # was: "data.tsm:40:17: error: store PositionStore: the period of PositionInDEG must
    # be positive", at the store, far from the value that made it so
    product = DATA / "products" / "both_fast_refresh.yaml"
    result = run(
        "resolve",
        DATA,
        "--features",
        product,
        "--set",
        f"FastRefresh.period={value}",
        "-o",
        tmp_path / "b",
    )
    assert result.exit_code == 1 and not (tmp_path / "b").exists()
    shown = repr(float(value))
    assert errors(result)[0] == (
        f"{DATA / 'data.rm'}:21:5: error: the transformer period of PositionStore.PositionInDEG "
        f"cannot be feature attribute FastRefresh.period = {shown} s: it must be at least "
        "0.001 s and at most a year"
    )


@pytest.mark.parametrize("second", ["robot_1", "ROBOT_1"])
def test_check_warns_of_robot_ids_every_product_keeping_both_fails_on(tmp_path, second):
    # was: spl check 0 errors, 0 warnings; then every resolve refused
    line = two_robot_line(tmp_path, "robot_1", second)
    result = run("check", line)
    assert result.exit_code == 0
    assert [e for e in result.stderr.splitlines() if "SPL017" in e] == [
        f"{line / 'l.tsm'}:3:22: warning: robot container R1 has robot_id {second!r}, as robot "
        "container R0 has 'robot_1': a product keeping both fails to resolve unless its "
        "deployment sets another for one [SPL017]"
    ]
    assert "SPL019" not in result.stderr  # robots alike are SPL017's alone


def test_a_group_asking_for_more_features_than_it_has_is_refused(tmp_path):
    # was: spl check "ok" for a void model (root R group [5..5] { A B })
    path = tmp_path / "void.fm"
    path.write_text("feature model V\nroot R group [5..5] { A B }\n", encoding="utf-8")
    result = run("check", path)
    assert result.exit_code == 1
    assert errors(result) == [
        f"{path}:2:8: error: bad cardinality [5..5]: the group has 2 features, fewer than its "
        "lower bound (no product could choose that many)"
    ]
    # the bounds as written (was "[3..]" for each of these)
    path.write_text(
        "feature model V\nroot R {\n optional F group [3..*] { A B }\n"
        " optional G group [3] { C D }\n}\n",
        encoding="utf-8",
    )
    assert [e.split(": ")[2] for e in errors(run("check", path))] == [
        "bad cardinality [3..*]",
        "bad cardinality [3]",
    ]


@pytest.mark.parametrize("value", ["5e-324", "0.0009", "1e9"])
def test_a_period_literal_out_of_range_is_refused_by_the_rm(tmp_path, value):
    # was: 5e-324 s (a busy loop) accepted; 1e9 passed the .rm and failed only at resolve
    line = tmp_path / "data"
    shutil.copytree(DATA, line)
    rm = line / "data.rm"
    text = rm.read_text(encoding="utf-8")
    used = "parameter PositionStore.PositionInDEG.period = feature FastRefresh.period"
    assert used in text
    rm.write_text(text.replace(used, used.replace("feature FastRefresh.period", value)))
    result = run("check", line)
    assert result.exit_code == 1
    assert errors(result) == [
        f"{rm}:21:5: error: PositionStore.PositionInDEG.period must be at least 0.001 s and "
        "at most a year"
    ]
