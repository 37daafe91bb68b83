"""Packages found without options: the description's source tree, then the environment; a
missing package reported only when the expansion reaches it, with the include chain."""

from __future__ import annotations

from pathlib import Path

import pytest

import diffbot
from diffbot.errors import OutsideRootsError
from diffbot.urdf import packages
from diffbot.urdf.packages import (
    PackageFinder,
    given_package,
    own_package,
    package_name,
    packages_under,
    source_tree,
)

XACRO_NS = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'


def manifest(folder: Path, name: str) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "package.xml").write_text(
        f'<?xml version="1.0"?>\n<package format="3"><name>{name}</name>'
        "<version>1.0.0</version></package>\n",
        encoding="utf-8",
    )


WHEEL_MACRO = f"""<?xml version="1.0"?>
<robot {XACRO_NS}>
  <xacro:macro name="wheel" params="side y">
    <link name="${{side}}_wheel">
      <collision><origin rpy="1.5707963 0 0"/>
        <geometry><cylinder radius="0.098" length="0.04"/></geometry></collision>
    </link>
    <joint name="${{side}}_wheel_joint" type="continuous">
      <parent link="chassis_link"/><child link="${{side}}_wheel"/>
      <origin xyz="0 ${{y}} 0.0345"/><axis xyz="0 1 0"/>
    </joint>
  </xacro:macro>
</robot>
"""

#: Shaped like a Clearpath robot's top-level description: its own package's macros, a sibling
#: package's file, an accessory under a false ``xacro:if`` naming a package nobody has.
ROBOT = f"""<?xml version="1.0"?>
<robot name="j100" {XACRO_NS}>
  <xacro:arg name="onav" default="false"/>
  <xacro:include filename="$(find j100_description)/urdf/wheel.urdf.xacro"/>
  <xacro:include filename="$(find j100_control)/urdf/control.urdf.xacro"/>
  <xacro:if value="$(arg onav)">
    <xacro:include filename="$(find cpr_onav_description)/urdf/onav.urdf.xacro"/>
  </xacro:if>
  <link name="base_link"/>
  <link name="chassis_link"/>
  <joint name="chassis_joint" type="fixed"><parent link="base_link"/><child link="chassis_link"/>
  </joint>
  <xacro:wheel side="left" y="0.187795"/>
  <xacro:wheel side="right" y="-0.187795"/>
</robot>
"""

CONTROL = f"""<?xml version="1.0"?>
<robot {XACRO_NS}><gazebo><plugin filename="gz_ros2_control-system" name="c">
<parameters>$(find j100_control)/config/control.yaml</parameters></plugin></gazebo></robot>
"""

CONTROLLERS = """controller_manager:
  ros__parameters:
    platform_velocity_controller:
      type: diff_drive_controller/DiffDriveController
platform_velocity_controller:
  ros__parameters:
    left_wheel_names: [left_wheel_joint]
    right_wheel_names: [right_wheel_joint]
    wheel_separation: 0.37559
    wheel_radius: 0.098
"""


def clone(tmp_path: Path, *, git: bool = True) -> Path:
    """A repository holding a description package and its sibling control package (the
    folder names differ from the package names, as in many repositories)."""
    repo = tmp_path / "clone"
    if git:
        (repo / ".git").mkdir(parents=True)
    description = repo / "description"
    manifest(description, "j100_description")
    (description / "urdf").mkdir()
    (description / "urdf" / "wheel.urdf.xacro").write_text(WHEEL_MACRO, encoding="utf-8")
    robot = description / "urdf" / "j100.urdf.xacro"
    robot.write_text(ROBOT, encoding="utf-8")
    control = repo / "platform" / "control"
    manifest(control, "j100_control")
    (control / "urdf").mkdir()
    (control / "config").mkdir()
    (control / "urdf" / "control.urdf.xacro").write_text(CONTROL, encoding="utf-8")
    (control / "config" / "control.yaml").write_text(CONTROLLERS, encoding="utf-8")
    return robot


def test_sibling_packages_of_the_source_tree_need_no_option(tmp_path: Path) -> None:
    robot = clone(tmp_path)
    params = diffbot.load_params(robot)
    assert params.wheel_separation == pytest.approx(0.37559, abs=1e-12)
    controllers = tmp_path / "clone/platform/control/config/control.yaml"
    assert params.sources["wheel_separation"] == f"controllers:{controllers}"
    # the sibling package's files were read, and said so
    assert controllers.parent.parent / "urdf" / "control.urdf.xacro" in map(
        Path, params.description_files
    )


def test_a_package_is_named_by_its_manifest_not_its_folder(tmp_path: Path) -> None:
    robot = clone(tmp_path)
    found = packages_under(source_tree(robot) or tmp_path)
    assert found["j100_control"] == tmp_path / "clone" / "platform" / "control"
    assert "control" not in found
    assert package_name(tmp_path / "clone" / "description") == "j100_description"


def test_the_tree_is_the_repository_holding_the_package(tmp_path: Path) -> None:
    robot = clone(tmp_path)
    assert source_tree(robot) == tmp_path / "clone"


def test_without_a_repository_the_tree_is_the_packages_parent(tmp_path: Path) -> None:
    robot = clone(tmp_path, git=False)
    assert source_tree(robot) == tmp_path / "clone"


def test_a_workspace_src_folder_is_the_tree(tmp_path: Path) -> None:
    package = tmp_path / "ws" / "src" / "robots" / "my_description"
    manifest(package, "my_description")
    manifest(tmp_path / "ws" / "src" / "tools" / "my_control", "my_control")
    assert source_tree(package / "robot.urdf") == tmp_path / "ws" / "src"
    assert set(packages_under(tmp_path / "ws" / "src")) == {"my_description", "my_control"}


def test_a_description_outside_any_package_searches_no_tree(tmp_path: Path) -> None:
    assert source_tree(tmp_path / "robot.urdf") is None


def test_a_false_condition_never_asks_for_its_package(tmp_path: Path) -> None:
    # cpr_onav_description exists nowhere: only the evaluated path counts
    robot = clone(tmp_path)
    assert diffbot.load_params(robot).left_joint == "left_wheel_joint"
    with pytest.raises(
        diffbot.PackageNotFoundError,
        match=r"^package 'cpr_onav_description' not found \(needed by j100\.urdf\.xacro\): "
        r"give its directory with packages: cpr_onav_description=DIR$",
    ):
        diffbot.load_params(robot, {"onav": "true"})


def test_another_top_level_file_in_the_folder_is_not_scanned(tmp_path: Path) -> None:
    robot = clone(tmp_path)
    other = robot.parent / "arm.urdf.xacro"
    other.write_text(
        f'<robot {XACRO_NS}><xacro:include filename="$(find ur_description)/ur.xacro"/></robot>',
        encoding="utf-8",
    )
    assert diffbot.load_params(robot).right_joint == "right_wheel_joint"


def test_a_missing_package_names_the_include_chain_that_asked(tmp_path: Path) -> None:
    robot = clone(tmp_path)
    wheel = robot.parent / "wheel.urdf.xacro"
    wheel.write_text(
        WHEEL_MACRO.replace(
            "<xacro:macro",
            '<xacro:include filename="$(find tyre_models)/tyre.xacro"/><xacro:macro',
        ),
        encoding="utf-8",
    )
    with pytest.raises(diffbot.PackageNotFoundError, match="tyre_models") as caught:
        diffbot.load_params(robot)
    assert "(needed by wheel.urdf.xacro <- j100.urdf.xacro)" in str(caught.value)
    assert caught.value.fields["missing"] == ["tyre_models"]


def test_a_given_package_wins_over_the_tree(tmp_path: Path) -> None:
    robot = clone(tmp_path)
    elsewhere = tmp_path / "elsewhere"
    (elsewhere / "urdf").mkdir(parents=True)
    (elsewhere / "urdf" / "control.urdf.xacro").write_text(f"<robot {XACRO_NS}/>", encoding="utf-8")
    params = diffbot.load_params(robot, packages={"j100_control": elsewhere})
    assert params.controller is None  # the given package names no controllers file


def test_packages_are_found_under_ros_package_path_and_ament_prefix_path(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    manifest(tmp_path / "catkin" / "src" / "deep" / "er" / "tyres", "tyre_models")
    (tmp_path / "prefix" / "share" / "ament_pkg").mkdir(parents=True)
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(tmp_path / "catkin" / "src"))
    monkeypatch.setenv("AMENT_PREFIX_PATH", str(tmp_path / "prefix"))
    finder = PackageFinder(None, {})
    assert finder.locate("tyre_models") == tmp_path / "catkin/src/deep/er/tyres"
    assert finder.locate("ament_pkg") == tmp_path / "prefix/share/ament_pkg"
    assert finder.locate("nowhere") is None


def test_ignored_hidden_and_build_folders_are_not_searched(tmp_path: Path) -> None:
    root = tmp_path / "tree"
    manifest(root / "kept", "kept")
    manifest(root / "ignored" / "pkg", "ignored_pkg")
    (root / "ignored" / "COLCON_IGNORE").write_text("", encoding="utf-8")
    manifest(root / ".hidden" / "pkg", "hidden_pkg")
    manifest(root / "build" / "pkg", "built_pkg")
    assert set(packages_under(root)) == {"kept"}


def test_the_search_is_bounded(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    root = tmp_path / "wide"
    for k in range(30):
        (root / f"d{k:02d}").mkdir(parents=True)
    manifest(root / "zz", "last")
    monkeypatch.setattr(packages, "MAX_FOLDERS", 10)
    packages_under.cache_clear()
    assert "last" not in packages_under(root)
    packages_under.cache_clear()


def test_a_tree_package_is_readable_but_nothing_outside_the_tree(tmp_path: Path) -> None:
    robot = clone(tmp_path)
    secret = tmp_path / "secret.xacro"
    secret.write_text(f"<robot {XACRO_NS}/>", encoding="utf-8")
    robot.write_text(
        ROBOT.replace(
            '<link name="base_link"/>',
            f'<xacro:include filename="{secret}"/><link name="base_link"/>',
        ),
        encoding="utf-8",
    )
    with pytest.raises(OutsideRootsError, match="refused in an untrusted description"):
        diffbot.load_params(robot)


def test_a_workspace_wins_over_the_repository_for_repositories_side_by_side(
    tmp_path: Path,
) -> None:
    src = tmp_path / "ws" / "src"
    (src / "robot" / ".git").mkdir(parents=True)
    manifest(src / "robot" / "robot_description", "robot_description")
    manifest(src / "sensors" / "lidar_description", "lidar_description")
    description = src / "robot" / "robot_description" / "urdf" / "robot.urdf.xacro"
    assert source_tree(description) == src
    assert PackageFinder(description, {}).locate("lidar_description") == (
        src / "sensors" / "lidar_description"
    )


@pytest.mark.parametrize("name", ["a", "ros2_control", "gz-ros2-control", "Pkg.v2", "_x"])
def test_plain_package_names(name: str) -> None:
    assert packages.plain_name(name)


@pytest.mark.parametrize("name", ["", ".", "..", ".hidden", "/etc", "a/b", "../x", "a\\b", "a b"])
def test_names_that_are_paths_are_no_package_names(name: str) -> None:
    assert not packages.plain_name(name)


def secret_folder(tmp_path: Path) -> Path:
    secret = tmp_path / "secret"
    secret.mkdir()
    (secret / "s.xacro").write_text(
        f'<robot {XACRO_NS}><link name="SECRET_CONTENT"/></robot>', encoding="utf-8"
    )
    return secret


@pytest.mark.parametrize("variable", ["AMENT_PREFIX_PATH", "ROS_PACKAGE_PATH"])
@pytest.mark.parametrize("how", ["absolute", "dotdot", "parent"])
def test_find_of_a_path_reaches_nothing_outside_the_descriptions_folders(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, variable: str, how: str
) -> None:
    # $(find NAME) adds NAME's folder to those the description may read: a NAME that is a path
    # would open any folder, through a search folder that joins it as it is.
    from cli_results import assert_one_error_line
    from click.testing import CliRunner

    from diffbot.cli import main

    secret = secret_folder(tmp_path)
    prefix = tmp_path / "prefix" / "share"
    prefix.mkdir(parents=True)
    monkeypatch.setenv(variable, str(tmp_path / "prefix"))
    name = {"absolute": str(secret), "dotdot": "../../secret", "parent": ".."}[how]
    include = "$(find ..)/secret/s.xacro" if how == "parent" else f"$(find {name})/s.xacro"
    robot = tmp_path / "desc" / "robot.urdf.xacro"
    robot.parent.mkdir()
    robot.write_text(
        f'<?xml version="1.0"?>\n<robot name="r" {XACRO_NS}><xacro:include filename="{include}"/>'
        "</robot>\n",
        encoding="utf-8",
    )
    assert PackageFinder(robot, {}).locate(name) is None
    result = CliRunner().invoke(main, ["urdf", str(robot)])
    assert "SECRET_CONTENT" not in result.output
    assert_one_error_line(result, "not found")


def test_a_package_linked_into_a_prefix_is_found_but_no_path_through_it(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # An install may link its packages: the environment's folders are the user's own. Only the
    # name is the description's, and it never walks out of them.
    secret = secret_folder(tmp_path)
    share = tmp_path / "prefix" / "share"
    share.mkdir(parents=True)
    (share / "linked").symlink_to(secret, target_is_directory=True)
    monkeypatch.setenv("AMENT_PREFIX_PATH", str(tmp_path / "prefix"))
    finder = PackageFinder(None, {})
    assert finder.locate("linked") == share / "linked"
    assert finder.locate("linked/..") is None
    assert finder.locate("../share/linked") is None


def test_the_own_package_is_the_nearest_manifest_at_any_depth(tmp_path: Path) -> None:
    package = tmp_path / "fleet_description"
    manifest(package, "fleet_description")
    deep = package / "batch" / "courier_b" / "variants" / "v2" / "urdf" / "courier.urdf.xacro"
    deep.parent.mkdir(parents=True)
    assert own_package(deep) == package
    manifest(package / "batch" / "courier_b", "courier_b")  # a nearer one wins
    assert own_package(deep) == package / "batch" / "courier_b"


def test_the_home_folder_is_no_package(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("HOME", str(tmp_path))
    manifest(tmp_path, "stray")
    (tmp_path / "robots" / "urdf").mkdir(parents=True)
    assert own_package(tmp_path / "robots" / "urdf" / "robot.urdf") is None


def test_a_given_package_may_be_its_folder_an_install_prefix_or_a_share_folder(
    tmp_path: Path,
) -> None:
    source = tmp_path / "src" / "tyres"
    manifest(source, "tyre_models")
    installed = tmp_path / "install" / "tyre_models" / "share" / "tyre_models"
    manifest(installed, "tyre_models")
    prefix = tmp_path / "install" / "tyre_models"
    assert given_package("tyre_models", source) == source
    assert given_package("tyre_models", prefix) == installed
    assert given_package("tyre_models", prefix / "share") == installed
    # a folder that is none of them is taken as it is (a package without a manifest)
    assert given_package("tyre_models", tmp_path / "loose") == tmp_path / "loose"
    assert given_package("../x", prefix) == prefix
    for folder in (source, prefix, prefix / "share"):
        finder = PackageFinder(None, {"tyre_models": folder})
        assert finder.locate("tyre_models") in (source, installed)


def test_an_install_prefix_resolves_find(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    robot = clone(tmp_path)
    share = tmp_path / "install" / "j100_control" / "share" / "j100_control"
    for folder in ("urdf", "config"):
        (share / folder).mkdir(parents=True)
        for file in (robot.parents[2] / "platform" / "control" / folder).iterdir():
            (share / folder / file.name).write_bytes(file.read_bytes())
    manifest(share, "j100_control")
    monkeypatch.chdir(tmp_path)
    params = diffbot.load_params(robot, packages={"j100_control": "install/j100_control"})
    # shown from the current folder, as the package was given
    controllers = "install/j100_control/share/j100_control/config/control.yaml"
    assert params.sources["wheel_separation"] == f"controllers:{controllers}"


def test_relative_environment_entries_are_from_the_current_folder(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    manifest(tmp_path / "ws" / "install" / "tyres" / "share" / "tyres", "tyres")
    manifest(tmp_path / "ws" / "src" / "rims", "rims")
    monkeypatch.chdir(tmp_path / "ws")
    monkeypatch.setenv("AMENT_PREFIX_PATH", "install/tyres")
    monkeypatch.setenv("ROS_PACKAGE_PATH", "src")
    finder = PackageFinder(None, {})
    # absolute: xacro takes a relative $(find) from the including file's folder
    assert finder.locate("tyres") == tmp_path / "ws/install/tyres/share/tyres"
    assert finder.locate("rims") == tmp_path / "ws/src/rims"


def test_paths_are_shown_as_the_user_gave_them(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    manifest(tmp_path / "install" / "tyres" / "share" / "tyres", "tyres")
    manifest(tmp_path / "ws" / "desc", "desc")
    monkeypatch.chdir(tmp_path / "ws")
    finder = PackageFinder(Path("desc/robot.urdf"), {"tyres": "../install/tyres"})
    inside = tmp_path / "install/tyres/share/tyres/urdf/t.xacro"
    assert finder.shown(inside) == "../install/tyres/share/tyres/urdf/t.xacro"
    assert finder.shown(tmp_path / "install/tyres/share/tyres") == "../install/tyres/share/tyres"
    assert finder.shown(tmp_path / "ws/desc/urdf/w.xacro") == "desc/urdf/w.xacro"
    assert finder.shown(tmp_path / "elsewhere.xacro") == str(tmp_path / "elsewhere.xacro")
    absolute = PackageFinder(tmp_path / "ws/desc/robot.urdf", {"tyres": tmp_path / "install"})
    assert absolute.shown(tmp_path / "ws/desc/urdf/w.xacro") == str(
        tmp_path / "ws/desc/urdf/w.xacro"
    )
    assert absolute.shown(inside) == str(inside)


def test_the_climb_to_the_own_package_is_bounded(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    manifest(tmp_path / "pkg", "pkg")
    description = tmp_path / "pkg" / "a" / "b" / "robot.urdf"
    assert own_package(description) == tmp_path / "pkg"
    monkeypatch.setattr(packages, "PACKAGE_LEVELS", 2)  # b, a: not pkg
    assert own_package(description) is None


def test_a_given_folder_that_holds_another_package_is_read_with_a_warning(
    tmp_path: Path,
) -> None:
    robot = clone(tmp_path)
    elsewhere = tmp_path / "elsewhere"
    manifest(elsewhere, "j100_bringup")
    (elsewhere / "urdf").mkdir()
    (elsewhere / "urdf" / "control.urdf.xacro").write_text(f"<robot {XACRO_NS}/>", encoding="utf-8")
    expansion = diffbot.expand(robot, packages={"j100_control": elsewhere})
    said = [w for w in expansion.warnings if "j100_control" in w]
    assert said == [
        f"the folder given for package 'j100_control' ({elsewhere}) holds package "
        "'j100_bringup': $(find j100_control) reads it all the same"
    ]
    # A folder holding the package asked for, or no manifest at all, is taken without a word.
    manifest(elsewhere, "j100_control")
    assert diffbot.expand(robot, packages={"j100_control": elsewhere}).warnings == ()
    (elsewhere / "package.xml").unlink()
    assert diffbot.expand(robot, packages={"j100_control": elsewhere}).warnings == ()
