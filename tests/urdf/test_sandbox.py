"""The xacro sandbox: real descriptions expand, hostile ones are refused quickly and cleanly."""

from __future__ import annotations

import math
import re
import threading
import time
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st
from linear_time import assert_linear

import diffbot
from diffbot.errors import (
    DescriptionError,
    ExpansionLimitError,
    OutsideRootsError,
    RefusedExpressionError,
    SandboxError,
    XacroError,
)
from diffbot.urdf import sandbox
from diffbot.urdf.expression_limits import MAX_INT_BITS
from diffbot.urdf.expressions import safe_eval
from diffbot.urdf.sandbox import Reads, description_roots, process, sandboxed

XACRO_NS = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'
REFUSED = r"refused in an untrusted description: it uses "


def refused(reason: str) -> str:
    """The pattern of a refusal for ``reason``, with its hint that trust restores xacro."""
    return REFUSED + reason + r".*\(trust=True\)"


BUNDLED = Path(diffbot.__file__).resolve().parent / "description"


def write(path: Path, text: str) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    return path


def robot(body: str) -> str:
    return f'<?xml version="1.0"?>\n<robot name="test" {XACRO_NS}>\n{body}\n</robot>\n'


def floats(text: str) -> list[float]:
    return [float(x) for x in text.split()]


def outside(what: str) -> str:
    """The pattern of a refused file read, with its hint that trust restores xacro."""
    return what + r".*refused in an untrusted description: it is outside.*\(trust=True\)"


# --- a real description, written for these tests -------------------------------------------------


@pytest.fixture
def demo(tmp_path: Path) -> Path:
    """A package with a YAML file, a namespaced include, and a second package found by name."""
    package = tmp_path / "demo_description"
    write(package / "package.xml", "<package><name>demo_description</name></package>\n")
    write(
        package / "config" / "props.yaml",
        "wheel:\n  radius: 0.05\n  name: hub\n  tilt: !degrees 90\nwidth: !millimeters 20\n",
    )
    write(
        package / "urdf" / "wheel.xacro",
        robot(
            '<xacro:property name="offset" value="0.1"/>\n'
            '<xacro:macro name="wheel" params="side y">\n'
            '  <link name="${side}_wheel"><origin xyz="0 ${y} 0"/></link>\n'
            "</xacro:macro>"
        ),
    )
    write(
        tmp_path / "parts" / "parts.xacro",
        robot(
            '<xacro:macro name="box_link" params="name *origin">\n'
            '  <link name="${name}"><xacro:insert_block name="origin"/></link>\n'
            "</xacro:macro>"
        ),
    )
    return write(
        package / "urdf" / "demo.urdf.xacro",
        robot(
            '<xacro:arg name="prefix" default="demo_"/>\n'
            '<xacro:property name="props" value="${xacro.load_yaml(\'../config/props.yaml\')}"/>\n'
            "<xacro:property name=\"r\" value=\"${props['wheel']['radius']}\"/>\n"
            '<xacro:property name="mode" value="$(optenv DIFFBOT_SANDBOX_MODE wide)"/>\n'
            '<xacro:include filename="$(find parts)/parts.xacro"/>\n'
            '<xacro:include filename="wheel.xacro" ns="left"/>\n'
            '<link name="$(arg prefix)base"/>\n'
            '<xacro:box_link name="chassis"><origin xyz="0 0 ${r}"/></xacro:box_link>\n'
            '<xacro:left.wheel side="left" y="${left.offset}"/>\n'
            '<joint name="tilt"><origin rpy="${pi/2} ${radians(90)} 0" xyz="${sqrt(2)*r} 0 0"/>'
            "</joint>\n"
            '<xacro:if value="${mode == \'wide\'}"><link name="wide"/></xacro:if>\n'
            '<xacro:unless value="${mode == \'wide\'}"><link name="narrow"/></xacro:unless>\n'
            "<link name=\"${'wheel_' + props.wheel.name}\"/>\n"
            "<link name=\"size_${'%.3f' % r}\"/>\n"
            '<joint name="units"><origin rpy="0 ${props.wheel.tilt} 0" xyz="${props.width} 0 0"/>'
            "</joint>\n"
            "<link name=\"$(eval prefix + 'evaled_' + '%d' % 6)\"/>"
        ),
    )


def find_parts(demo: Path) -> dict[str, str]:
    return {"parts": str(demo.parents[2] / "parts")}


def expand_demo(demo: Path, *, trust: bool = False) -> str:
    return process(demo, {"prefix": "my_"}, find=find_parts(demo).__getitem__, trust=trust)


def test_a_real_description_expands_in_the_sandbox_as_with_full_trust(demo: Path) -> None:
    assert expand_demo(demo) == expand_demo(demo, trust=True)


@pytest.mark.parametrize("trust", [False, True])
def test_the_record_of_reads_holds_every_file_and_folder_the_expansion_read(
    demo: Path, trust: bool
) -> None:
    reads = Reads()
    process(demo, find=find_parts(demo).__getitem__, trust=trust, reads=reads)
    package, parts = demo.parents[1], demo.parents[2] / "parts"
    assert set(reads.files) == {
        demo,
        package / "config" / "props.yaml",
        parts / "parts.xacro",
        package / "urdf" / "wheel.xacro",
    }
    assert {package, package / "urdf", parts} <= set(reads.folders)
    assert len(reads.folders) == len(set(reads.folders))


def test_the_record_of_reads_holds_what_was_read_before_an_expansion_failed(
    tmp_path: Path,
) -> None:
    write(tmp_path / "part.xacro", robot('<link name="part"/>'))
    body = '<xacro:include filename="part.xacro"/><link name="${undefined_name}"/>'
    path = write(tmp_path / "robot.urdf.xacro", robot(body))
    reads = Reads()
    with pytest.raises(XacroError):
        process(path, reads=reads)
    assert set(reads.files) == {path, tmp_path / "part.xacro"}
    assert reads.folders == [tmp_path]


def test_yaml_properties_namespaces_blocks_and_math_reach_the_urdf(demo: Path) -> None:
    urdf = expand_demo(demo)
    chassis = ET.fromstring(urdf).find("link[@name='chassis']/origin")
    assert chassis is not None
    assert floats(chassis.attrib["xyz"]) == pytest.approx([0.0, 0.0, 0.05], abs=1e-12)
    left = ET.fromstring(urdf).find("link[@name='left_wheel']/origin")
    assert left is not None
    assert floats(left.attrib["xyz"]) == pytest.approx([0.0, 0.1, 0.0], abs=1e-12)
    tilt = ET.fromstring(urdf).find("joint[@name='tilt']/origin")
    assert tilt is not None
    assert floats(tilt.attrib["rpy"]) == pytest.approx([math.pi / 2, math.pi / 2, 0.0], abs=1e-12)
    assert floats(tilt.attrib["xyz"])[0] == pytest.approx(0.05 * math.sqrt(2), abs=1e-12)


def test_yaml_units_are_converted_to_si(demo: Path) -> None:
    units = ET.fromstring(expand_demo(demo)).find("joint[@name='units']/origin")
    assert units is not None
    assert floats(units.attrib["rpy"])[1] == pytest.approx(math.pi / 2, abs=1e-12)
    assert floats(units.attrib["xyz"])[0] == pytest.approx(0.02, abs=1e-12)


def test_the_sandbox_changes_nothing_in_what_xacro_produces(demo: Path) -> None:
    import xacro
    import xacro.substitution_args as subst

    saved = subst._eval_find
    subst._eval_find = find_parts(demo).__getitem__
    try:
        plain = xacro.process_file(str(demo), mappings={"prefix": "my_"}).toprettyxml(indent="  ")
    finally:
        subst._eval_find = saved
    assert expand_demo(demo) == plain


def test_arguments_conditionals_strings_and_eval_reach_the_urdf(demo: Path) -> None:
    names = {link.get("name") for link in ET.fromstring(expand_demo(demo)).iter("link")}
    assert {"my_base", "wide", "wheel_hub", "size_0.050", "my_evaled_6"} <= names
    assert "narrow" not in names


def test_optenv_reads_the_environment(demo: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("DIFFBOT_SANDBOX_MODE", "narrow")
    names = {link.get("name") for link in ET.fromstring(expand_demo(demo)).iter("link")}
    assert "narrow" in names
    assert "wide" not in names


def test_the_bundled_description_expands_in_the_sandbox_as_with_full_trust() -> None:
    path = BUNDLED / "diffbot.urdf.xacro"
    packages = {"diffbot_description": str(BUNDLED), "diffbot_control": str(BUNDLED)}
    sandboxed_urdf = process(path, find=packages.__getitem__)
    assert sandboxed_urdf == process(path, find=packages.__getitem__, trust=True)
    wheel = ET.fromstring(sandboxed_urdf).find("link[@name='front_left_wheel']/visual/geometry")
    assert wheel is not None
    assert float(wheel[0].attrib["radius"]) == pytest.approx(0.035, abs=1e-12)


def test_a_description_reads_its_package_folder_but_not_beyond(tmp_path: Path) -> None:
    package = tmp_path / "pkg"
    write(package / "package.xml", "<package/>\n")
    path = write(package / "urdf" / "robot.urdf.xacro", robot(""))
    assert description_roots(path) == (package / "urdf", package)
    assert description_roots(write(tmp_path / "alone" / "r.xacro", "")) == (tmp_path / "alone",)


# --- hostile descriptions ------------------------------------------------------------------------


def evaluated(tmp_path: Path, code: str) -> Path:
    """A description that runs ``code`` with ``$(eval)`` (through a property: no ``)`` inside)."""
    body = f'<xacro:property name="code" value="{code}"/>\n<link name="$(eval ${{code}})"/>'
    return write(tmp_path / "evil" / "evil.urdf.xacro", robot(body))


def test_eval_cannot_run_a_command(tmp_path: Path) -> None:
    marker = tmp_path / "ran"
    path = evaluated(tmp_path, f"exec('import os; os.system(&quot;touch {marker}&quot;)')")
    with pytest.raises(RefusedExpressionError, match=refused("the Python builtin 'exec'")):
        process(path)
    assert not marker.exists()


def test_eval_cannot_write_a_file_unless_trusted(tmp_path: Path) -> None:
    marker = tmp_path / "written"
    path = evaluated(tmp_path, f"open('{marker}', 'w').write('pwned')")
    with pytest.raises(RefusedExpressionError, match=refused("the Python builtin 'open'")):
        process(path)
    assert not marker.exists()
    process(path, trust=True)
    assert marker.read_text() == "pwned"


def test_eval_cannot_read_etc_passwd(tmp_path: Path) -> None:
    path = evaluated(tmp_path, "open('/etc/passwd').read()")
    with pytest.raises(RefusedExpressionError, match=refused("the Python builtin 'open'")):
        process(path)


def test_load_yaml_cannot_read_etc_passwd(tmp_path: Path) -> None:
    body = "<link name=\"${xacro.load_yaml('/etc/passwd')}\"/>"
    path = write(tmp_path / "evil" / "evil.urdf.xacro", robot(body))
    with pytest.raises(OutsideRootsError, match=outside("/etc/passwd: xacro.load_yaml")):
        process(path)


def test_load_yaml_cannot_climb_out_of_the_folder_or_follow_a_link(tmp_path: Path) -> None:
    secret = write(tmp_path / "secret.yaml", "key: secret\n")
    (tmp_path / "evil").mkdir()
    (tmp_path / "evil" / "link.yaml").symlink_to(secret)
    for name in ("../secret.yaml", "link.yaml"):
        body = f"<link name=\"${{xacro.load_yaml('{name}')['key']}}\"/>"
        path = write(tmp_path / "evil" / "evil.urdf.xacro", robot(body))
        with pytest.raises(OutsideRootsError, match=outside("")):
            process(path)
        assert "secret" in process(path, trust=True)


def test_load_yaml_reads_the_file_it_checked_from_any_current_folder(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # A description named by a relative path with a folder (urdf/robot.urdf.xacro, run from the
    # repository): the name is taken from the description's folder once, not twice, whatever
    # the current folder. A link where the doubled name would lead goes outside the tree.
    body = "<link name=\"${xacro.load_yaml('etc/wheel.yaml')['radius']}\"/>"
    write(tmp_path / "repo" / "urdf" / "robot.urdf.xacro", robot(body))
    write(tmp_path / "repo" / "urdf" / "etc" / "wheel.yaml", "radius: 0.05\n")
    write(tmp_path / "outside" / "etc" / "wheel.yaml", "radius: 0.07\n")
    (tmp_path / "repo" / "urdf" / "urdf").symlink_to(tmp_path / "outside")
    for folder, name in (
        (tmp_path / "repo", "urdf/robot.urdf.xacro"),
        (tmp_path, "repo/urdf/robot.urdf.xacro"),
    ):
        monkeypatch.chdir(folder)
        expanded = process(name)
        assert 'name="0.05"' in expanded
        assert "0.07" not in expanded


def test_an_include_outside_the_folders_is_refused(tmp_path: Path) -> None:
    write(tmp_path / "elsewhere.xacro", robot('<link name="elsewhere"/>'))
    body = f'<xacro:include filename="{tmp_path / "elsewhere.xacro"}"/>'
    path = write(tmp_path / "evil" / "evil.urdf.xacro", robot(body))
    with pytest.raises(OutsideRootsError, match=outside(r"elsewhere\.xacro: reading")):
        process(path)
    assert 'name="elsewhere"' in process(path, roots=[tmp_path])


def test_a_wildcard_include_lists_no_folder_outside_and_names_none_of_its_files(
    tmp_path: Path,
) -> None:
    write(tmp_path / "elsewhere" / "secret_name.xacro", robot('<link name="elsewhere"/>'))
    inside = write(tmp_path / "evil" / "parts" / "arm.xacro", robot('<link name="arm"/>'))
    (tmp_path / "evil" / "linked").symlink_to(tmp_path / "elsewhere")
    for pattern, folder in [
        (f"{tmp_path}/elsewhere/*.xacro", "elsewhere"),
        ("../elsewhere/*.xacro", "elsewhere"),
        ("*/../../elsewhere/*.xacro", "elsewhere"),  # out of the tree past a wildcard
        ("linked/*.xacro", "linked"),  # a link inside the tree to a folder outside
    ]:
        path = write(
            tmp_path / "evil" / "e.urdf.xacro", robot(f'<xacro:include filename="{pattern}"/>')
        )
        with pytest.raises(OutsideRootsError, match=outside(rf"{folder}: listing")) as caught:
            process(path)
        assert "secret_name" not in str(caught.value), pattern
    # Within the tree the wildcard includes as xacro's does; trusted, anywhere.
    path = write(
        tmp_path / "evil" / "e.urdf.xacro", robot('<xacro:include filename="p*/*.xacro"/>')
    )
    assert 'name="arm"' in process(path)
    assert inside.exists()
    body = f'<xacro:include filename="{tmp_path}/elsewhere/*.xacro"/>'
    path = write(tmp_path / "evil" / "e.urdf.xacro", robot(body))
    assert 'name="elsewhere"' in process(path, trust=True)


def test_a_description_installed_as_links_includes_from_the_folder_it_is_named_in(
    tmp_path: Path,
) -> None:
    """``colcon build --symlink-install``: the install tree's folders are real, its files links
    to the source tree's; a wildcard include lists the install tree's folder."""
    source = tmp_path / "src" / "pkg"
    write(source / "package.xml", "<package/>")
    write(source / "urdf" / "parts" / "arm.xacro", robot('<link name="arm"/>'))
    body = '<xacro:include filename="parts/*.xacro"/><link name="base"/>'
    write(source / "urdf" / "robot.urdf.xacro", robot(body))
    share = tmp_path / "install" / "pkg" / "share" / "pkg"
    for name in ("package.xml", "urdf/robot.urdf.xacro", "urdf/parts/arm.xacro"):
        (share / name).parent.mkdir(parents=True, exist_ok=True)
        (share / name).symlink_to(source / name)
    assert 'name="arm"' in process(share / "urdf" / "robot.urdf.xacro")
    assert set(description_roots(share / "urdf" / "robot.urdf.xacro")) == {
        share / "urdf",
        share,
        source / "urdf",
        source,
    }


def test_import_and_dunder_walks_are_refused(tmp_path: Path) -> None:
    marker = tmp_path / "imported"
    for expression, reason in [
        (f"__import__('os').system('touch {marker}')", "the name '__import__'"),
        ("().__class__.__bases__[0].__subclasses__()", "the attribute '__class__'"),
        ("python.type(1)", "the Python builtin 'type'"),
    ]:
        path = write(tmp_path / "evil" / "e.urdf.xacro", robot(f'<link name="${{{expression}}}"/>'))
        with pytest.raises(RefusedExpressionError, match=reason):
            process(path)
    assert not marker.exists()


def test_a_macro_that_doubles_itself_thirty_times_fails_fast(tmp_path: Path) -> None:
    body = (
        '<xacro:macro name="double" params="n">\n'
        '  <xacro:if value="${n > 0}">\n'
        '    <xacro:double n="${n - 1}"/><xacro:double n="${n - 1}"/>\n'
        "  </xacro:if>\n"
        '  <link name="l${n}"/>\n'
        "</xacro:macro>\n"
        '<xacro:double n="30"/>'
    )
    path = write(tmp_path / "evil" / "double.urdf.xacro", robot(body))
    # The work stops at the limit, whatever the 2^31 elements asked for: CPU time (not wall
    # time, whatever else the machine runs) grows with the limit, a few hundred microseconds an
    # element as xacro goes, and the default limit is refused as well.
    with pytest.raises(ExpansionLimitError, match=r"more than 500 elements \(max_elements\)"):
        process(path, max_elements=500)
    start = time.process_time()
    with pytest.raises(ExpansionLimitError, match=r"more than 500 elements \(max_elements\)"):
        process(path, max_elements=500)
    assert time.process_time() - start < 1.0
    start = time.process_time()
    with pytest.raises(ExpansionLimitError, match=r"more than \d+ elements \(max_elements\)"):
        process(path)
    assert time.process_time() - start < 20.0


COSTLY = (
    '<xacro:macro name="m" params="n"><xacro:if value="${n > 0}">\n'
    '  <foo v="${len(python.sorted([0] * 200000))}"/>\n'
    '  <xacro:m n="${n - 1}"/><xacro:m n="${n - 1}"/>\n'
    "</xacro:if></xacro:macro>\n"
    '<xacro:m n="12"/>'
)


@pytest.mark.parametrize("trust", [False, True])
def test_a_costly_expression_evaluated_over_and_over_runs_out_of_time(
    tmp_path: Path, trust: bool
) -> None:
    # 4095 sorts of 200,000 items, each allowed by its size and under the element limit: the
    # expansion's CPU time is bounded as well, between elements and expressions.
    path = write(tmp_path / "evil" / "costly.urdf.xacro", robot(COSTLY))
    start = time.thread_time()
    with pytest.raises(ExpansionLimitError, match=r"more than 0\.3 s of CPU time \(max_seconds\)"):
        process(path, trust=trust, max_seconds=0.3)
    assert time.thread_time() - start < 1.5
    assert sandbox.MAX_SECONDS == 10.0


def test_one_expression_runs_out_of_time_between_its_steps(tmp_path: Path) -> None:
    # One expression of many steps, each linear in a 450,000-item list: the budget is checked
    # at each step, not only once the expression is done.
    steps = ", ".join(["1 in p"] * 1000)
    body = f'<xacro:property name="p" value="${{[0] * 450000}}"/>\n<link name="${{[{steps}]}}"/>'
    path = write(tmp_path / "evil" / "steps.urdf.xacro", robot(body))
    start = time.thread_time()
    with pytest.raises(ExpansionLimitError, match=r"max_seconds"):
        process(path, max_seconds=0.2)
    assert time.thread_time() - start < 1.0
    ticks: list[None] = []
    assert safe_eval("1 + x * 2", {"x": 3}, tick=lambda: ticks.append(None)) == 7
    assert len(ticks) == 5  # 1, x, 2, x * 2, the sum


def test_python_sum_joins_lists_in_linear_time() -> None:
    assert safe_eval("python.sum([1, 2.5, 3])", {}) == 6.5
    assert safe_eval("python.sum([[1], [2, 3]], [0])", {}) == [0, 1, 2, 3]
    assert safe_eval("python.sum(((1,), (2,)), ())", {}) == (1, 2)
    with pytest.raises(TypeError, match=re.escape('can only concatenate list (not "tuple")')):
        safe_eval("python.sum([(1,)], [])", {})
    with pytest.raises(RefusedExpressionError, match=refused("a sum of more than")):
        safe_eval("python.sum(x, [])", {"x": [[0] * 1000] * 1001})
    timing = assert_linear(
        lambda text: safe_eval(f"len(python.sum([[1]] * {len(text)}, []))", {}),
        lambda n: b"x" * n,
        20_000,
        accepts=True,
    )
    assert timing.large < 1.0, timing


def test_a_huge_power_is_refused_fast(tmp_path: Path) -> None:
    path = write(tmp_path / "evil" / "power.urdf.xacro", robot('<link name="${9**9**9**9}"/>'))
    start = time.perf_counter()
    with pytest.raises(RefusedExpressionError, match=r"a power of more than 4096 bits.*trust=True"):
        process(path)
    assert time.perf_counter() - start < 0.5


def test_properties_that_double_a_string_hit_the_size_limit(tmp_path: Path) -> None:
    lines = ['<xacro:property name="p0" value="xxxxxxxxxxxxxxxx"/>']
    lines += [
        f'<xacro:property name="p{i}" value="${{p{i - 1}}}${{p{i - 1}}}"/>' for i in range(1, 40)
    ]
    path = write(
        tmp_path / "evil" / "laugh.urdf.xacro", robot("\n".join([*lines, "<a b='${p39}'/>"]))
    )
    with pytest.raises(ExpansionLimitError, match=r"more than 1000000 characters.*max_bytes"):
        process(path, max_bytes=1_000_000)


@pytest.mark.parametrize(("leaf", "levels"), [("x", 9), ('""', 6)])
def test_yaml_aliases_that_explode_hit_the_size_limit(
    tmp_path: Path, leaf: str, levels: int
) -> None:
    # six levels of ten empty strings are 1.2 million items: each counts, empty or not
    lines = [f"a0: &a0 [{', '.join([leaf] * 10)}]"]
    lines += [f"a{i}: &a{i} [{', '.join([f'*a{i - 1}'] * 10)}]" for i in range(1, levels)]
    write(tmp_path / "evil" / "lol.yaml", "\n".join(lines) + "\n")
    body = "<a b=\"${xacro.load_yaml('lol.yaml')}\"/>"
    path = write(tmp_path / "evil" / "lol.urdf.xacro", robot(body))
    with pytest.raises(ExpansionLimitError, match=r"max_bytes"):
        process(path, max_bytes=1_000_000)


def test_a_macro_calling_itself_forever_hits_the_depth_limit(tmp_path: Path) -> None:
    body = '<xacro:macro name="again"><xacro:again/></xacro:macro>\n<xacro:again/>'
    path = write(tmp_path / "evil" / "again.urdf.xacro", robot(body))
    with pytest.raises(ExpansionLimitError, match=r"macro calls nested more than 10 deep"):
        process(path, max_depth=10)


def test_a_file_including_itself_hits_the_default_depth_limit(tmp_path: Path) -> None:
    path = tmp_path / "evil" / "self.urdf.xacro"
    write(path, robot(f'<xacro:include filename="{path.name}"/>'))
    with pytest.raises(ExpansionLimitError, match=r"self.urdf.xacro: .*included files nested"):
        process(path)


def test_limits_hold_with_full_trust_too(tmp_path: Path) -> None:
    body = '<xacro:macro name="again"><xacro:again/></xacro:macro>\n<xacro:again/>'
    path = write(tmp_path / "evil" / "again.urdf.xacro", robot(body))
    with pytest.raises(ExpansionLimitError, match=r"max_depth"):
        process(path, trust=True, max_depth=10)


def test_trusted_eval_may_use_python_builtins_the_sandbox_refuses(tmp_path: Path) -> None:
    path = evaluated(tmp_path, "'-'.join(map(str, sorted([3, 1, 2])))")
    assert 'name="1-2-3"' in process(path, trust=True)
    with pytest.raises(RefusedExpressionError, match=refused("the Python builtin 'map'")):
        process(path)


def test_xacro_is_restored_after_a_refused_expansion(tmp_path: Path) -> None:
    import xacro
    import xacro.substitution_args as subst

    before = (xacro.safe_eval, xacro.eval_text, xacro.parse, xacro._global_symbols, subst._eval)
    path = write(tmp_path / "evil" / "power.urdf.xacro", robot('<link name="${9**9**9**9}"/>'))
    with pytest.raises(SandboxError, match="power"):
        process(path)
    after = (xacro.safe_eval, xacro.eval_text, xacro.parse, xacro._global_symbols, subst._eval)
    assert all(a is b for a, b in zip(before, after, strict=True))


@pytest.mark.parametrize("trust", [False, True])
def test_every_name_the_sandbox_gives_xacro_is_taken_back(tmp_path: Path, trust: bool) -> None:
    import xacro
    import xacro.substitution_args as subst

    modules = (vars(xacro), vars(subst), subst._eval_dict)
    before = [dict(names) for names in modules]
    body = '<link name="$(dirname)"/><xacro:include filename="parts/*.xacro"/>'
    path = write(tmp_path / "desc" / "robot.urdf.xacro", robot(body))
    write(tmp_path / "desc" / "parts" / "a.xacro", robot('<link name="a"/>'))
    assert 'name="a"' in process(path, trust=trust)
    changed = [
        sorted(name for name, value in names.items() if old.get(name, object()) is not value)
        for names, old in zip(modules, before, strict=True)
    ]
    assert changed == [["filestack", "macrostack"], [], []]  # xacro's own stacks, as it leaves them


def test_expansions_in_parallel_threads_each_get_their_own_result(demo: Path) -> None:
    expected = expand_demo(demo)
    results: list[str] = []

    def run() -> None:
        results.append(expand_demo(demo))

    threads = [threading.Thread(target=run) for _ in range(4)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert results == [expected] * 4


def test_the_sandbox_context_holds_around_a_plain_xacro_call(demo: Path) -> None:
    import xacro

    with sandboxed(demo, find=find_parts(demo).__getitem__):
        text = xacro.process_file(str(demo), mappings={}).toprettyxml()
    assert "wheel_hub" in text


# --- safe_eval on its own ------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("expression", "expected"),
    [
        ("pi / 2", math.pi / 2),
        ("radians(90)", math.pi / 2),
        ("degrees(pi)", 180.0),
        ("sqrt(2) * 0.05", 0.07071067811865476),
        ("atan2(1, -1)", 3 * math.pi / 4),
        ("hypot(3, 4)", 5.0),
        ("math.cos(pi)", -1.0),
        ("python.abs(-2.5)", 2.5),
        ("pow(2, 0.5)", math.sqrt(2)),
    ],
)
def test_math_functions_give_known_values(expression: str, expected: float) -> None:
    assert safe_eval(expression, {}) == pytest.approx(expected, abs=1e-12)


@pytest.mark.parametrize(
    ("expression", "expected"),
    [
        ("'%.3f' % r", "0.050"),
        ("f'{r:.2f}'", "0.05"),
        ("'a' + 'b' if r > 0 else 'c'", "ab"),
        ("props['a']['b']", 3),
        ("props.get('missing', 7)", 7),
        ("[1, 2, 3][1:]", [2, 3]),
        ("len(range(5))", 5),
        ("'left_wheel'.split('_')[0]", "left"),
        ("not (1 < r < 2) and r is not None", True),
        ("max([1, 5, 2])", 5),
        ("'_'.join(python.reversed(['a', 'b']))", "b_a"),
        ("round(0.12345, 3)", 0.123),
        ("2 ** 4095 > 0", True),
    ],
)
def test_everyday_expressions_give_known_values(expression: str, expected: object) -> None:
    assert safe_eval(expression, {"r": 0.05, "props": {"a": {"b": 3}}}) == expected


@pytest.mark.parametrize(
    ("expression", "reason"),
    [
        ("__import__('os')", "the name '__import__'"),
        ("eval('1')", "the Python builtin 'eval'"),
        ("compile('1', 'x', 'eval')", "the Python builtin 'compile'"),
        ("globals()", "the Python builtin 'globals'"),
        ("getattr(1, 'real')", "the Python builtin 'getattr'"),
        ("vars()", "the Python builtin 'vars'"),
        ("type(1)", "the Python builtin 'type'"),
        ("''.__class__", "the attribute '__class__'"),
        ("'{0.__class__}'.format(1)", "the attribute 'format'"),
        ("(1).real", "the attribute 'real'"),
        ("lambda: 1", "lambda"),
        ("[x for x in range(3)]", "a comprehension"),
        ("(x for x in range(3))", "a generator expression"),
        ("len(*[1])", "unpacking"),
        ("'x' * 10**7", "a repetition of more than"),
        ("[0] * 10**7", "a repetition of more than"),
        ("len([''] * 10**6 * 100)", "a repetition of more than"),
        ("'%9999d' % 1", "a format field wider than"),
        ("'%(a(b)c)9999d' % {'a(b)c': 1}", "a format field wider than"),
        ("'%(a)%(b)*d' % {'a': 1}", "a format field wider than"),
        ("range(10**9)", "a range of more than"),
        ("1 << 10**6", "a shift of more than"),
        ("python.pow(10, 10**6)", "a power of more than"),
        ("(10**1000) * (10**1000)", "a product of more than"),
        ("round(5, -10**9)", "rounding to more than"),
        ("'abcdefghij'.replace('', 'x' * 10**5)", "a replacement of more than"),
        ("'x'.center(10**7)", "a padding of more than"),
        ("b'x'", "the constant"),
    ],
)
def test_unsafe_or_unbounded_expressions_are_refused(expression: str, reason: str) -> None:
    with pytest.raises(RefusedExpressionError, match=refused(reason)):
        safe_eval(expression, {})


@given(
    st.text(alphabet="ab ,;-x]|(", max_size=40),
    st.text(alphabet=" ,;:/", min_size=1, max_size=4),
    st.booleans(),
)
def test_tokenize_cuts_as_xacro_does_at_plain_separators(
    text: str, sep: str, skip_empty: bool
) -> None:
    import xacro

    expected = xacro.tokenize(text, sep, skip_empty)
    assert safe_eval("xacro.tokenize(t, s, e)", {"t": text, "s": sep, "e": skip_empty}) == expected
    assert safe_eval("xacro.tokenize(t)", {"t": text}) == xacro.tokenize(text)


def test_tokenize_takes_each_character_of_its_separator_literally_in_linear_time() -> None:
    # xacro makes the pattern [SEP] of it: this one closes the class and backtracks 2**n times.
    crafted = "x]|(a|a)*[y"
    assert safe_eval("xacro.tokenize('a-b]c(d', ']-(')", {}) == ["a", "b", "c", "d"]
    timing = assert_linear(
        lambda text: safe_eval("xacro.tokenize(t, s)", {"t": text.decode(), "s": crafted}),
        lambda n: b"a" * n + b"!",
        4000,
        accepts=True,
    )
    assert timing.large < 1.0, timing


small = st.integers(min_value=-1000, max_value=1000)


@st.composite
def arithmetic(draw: st.DrawFn, depth: int = 3) -> str:
    if depth == 0 or draw(st.booleans()):
        return str(draw(small))
    op = draw(st.sampled_from(["+", "-", "*", "//", "%", "/", "<", "==", "and", "or"]))
    return f"({draw(arithmetic(depth - 1))} {op} {draw(arithmetic(depth - 1))})"


@given(arithmetic())
def test_arithmetic_agrees_with_python(expression: str) -> None:
    try:
        expected: object = eval(expression, {"__builtins__": {}})
    except ZeroDivisionError as err:
        with pytest.raises(ZeroDivisionError, match=re.escape(str(err))):
            safe_eval(expression, {})
        return
    assert safe_eval(expression, {}) == expected


@given(st.integers(min_value=2, max_value=10**6), st.integers(min_value=1, max_value=10**6))
def test_integer_powers_are_computed_exactly_or_refused_by_their_size(base: int, exp: int) -> None:
    if exp * math.log2(base) >= MAX_INT_BITS:
        with pytest.raises(RefusedExpressionError, match="a power of more than"):
            safe_eval(f"{base} ** {exp}", {})
    else:
        assert safe_eval(f"{base} ** {exp}", {}) == base**exp


def test_an_ordinary_xacro_failure_is_a_description_error(tmp_path: Path) -> None:
    path = write(tmp_path / "bad" / "bad.urdf.xacro", robot('<link name="${nope}"/>'))
    with pytest.raises(DescriptionError, match=r"xacro: name 'nope' is not defined"):
        process(path)


def test_every_refusal_is_a_description_error() -> None:
    for error in (RefusedExpressionError, OutsideRootsError, ExpansionLimitError):
        assert issubclass(error, SandboxError)
    assert issubclass(SandboxError, DescriptionError)


def test_a_missing_file_behind_find_names_the_includer_the_find_and_the_option(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    write(tmp_path / "ws" / "desc" / "package.xml", "<package><name>desc</name></package>")
    write(tmp_path / "other" / "tyres" / "package.xml", "<package><name>tyres</name></package>")
    robot = write(
        tmp_path / "ws" / "desc" / "urdf" / "robot.urdf.xacro",
        f'<robot name="r" {XACRO_NS}><xacro:include filename="$(find tyres)/urdf/t.xacro"/>'
        '<link name="base_link"/></robot>',
    )
    monkeypatch.chdir(tmp_path / "ws")
    with pytest.raises(DescriptionError) as raised:
        diffbot.load_params("desc/urdf/robot.urdf.xacro", packages={"tyres": "../other/tyres"})
    assert str(raised.value) == (
        "desc/urdf/robot.urdf.xacro includes $(find tyres)/urdf/t.xacro, but "
        "../other/tyres/urdf/t.xacro does not exist (package tyres is at ../other/tyres): if "
        "tyres is elsewhere, give the folder holding its package.xml with packages: tyres=DIR"
    )
    assert raised.value.fields["package"] == "tyres"
    # absolute stays absolute
    with pytest.raises(DescriptionError, match=re.escape(f"{robot} includes $(find tyres)")):
        diffbot.load_params(robot, packages={"tyres": tmp_path / "other" / "tyres"})
    # a missing file not behind a $(find) keeps its plain message
    write(robot, f'<robot name="r" {XACRO_NS}><xacro:include filename="nowhere.xacro"/></robot>')
    with pytest.raises(DescriptionError, match=r"nowhere\.xacro: no such file"):
        diffbot.load_params(robot)


def test_a_missing_yaml_behind_find_names_the_file_that_loads_it(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    write(tmp_path / "desc" / "package.xml", "<package><name>desc</name></package>")
    write(
        tmp_path / "desc" / "urdf" / "robot.urdf.xacro",
        f'<robot name="r" {XACRO_NS}>'
        '<xacro:property name="p" value="${xacro.load_yaml(\'$(find desc)/config/p.yaml\')}"/>'
        "<link name=\"${p['base']}\"/></robot>",
    )
    monkeypatch.chdir(tmp_path)
    with pytest.raises(DescriptionError) as raised:
        diffbot.load_params("desc/urdf/robot.urdf.xacro")
    assert str(raised.value).startswith(
        "desc/urdf/robot.urdf.xacro loads $(find desc)/config/p.yaml, but desc/config/p.yaml "
        "does not exist (package desc is at desc)"
    )


@pytest.mark.parametrize("trust", [False, True])
def test_dirname_is_the_folder_of_the_file_being_read(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, trust: bool
) -> None:
    # as ROS's xacro substitutes it: in an include's name, and in the included file its own
    part = write(tmp_path / "desc" / "parts" / "part.xacro", robot('<link name="in_$(dirname)"/>'))
    top = write(
        tmp_path / "desc" / "robot.urdf.xacro",
        robot(
            '<link name="top_$(dirname)"/><xacro:include filename="$(dirname)/parts/part.xacro"/>'
        ),
    )
    monkeypatch.chdir(tmp_path)  # another folder than the description's
    expanded = process(Path("desc") / top.name, trust=trust)
    assert f'name="top_{top.parent}"' in expanded
    assert f'name="in_{part.parent}"' in expanded


def test_sandboxed_takes_trust_only_as_a_bool(tmp_path: Path) -> None:
    """A truthy word lifts no sandbox: it is refused before xacro is patched."""
    robot = tmp_path / "r.urdf.xacro"
    robot.write_text('<robot name="r"/>')
    refused = pytest.raises(diffbot.ParameterError, match=r"^trust must be True or False")
    with refused, sandboxed(robot, trust="false"):  # type: ignore[arg-type]
        pass
