"""Where a controllers file's settings are found and how the file is read: node paths and
namespaces, sections declared in more than one place, repeated keys, wildcard sections, the
source each controller names, and the messages and bounds of reading the file
(diffbot.urdf.controllers)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from peak_memory import peak_bytes

from diffbot.urdf import controllers
from diffbot.urdf.controllers import (
    MAX_FILE_BYTES,
    ControllerConfigError,
    choose_controller,
    load_command_controllers,
    load_controllers,
    load_other_drive_controllers,
    node_base_name,
    other_drive_controllers,
    read_controllers,
)

DIFF = "diff_drive_controller/DiffDriveController"


# --- node names and sections ------------------------------------------------------------------


def test_a_node_path_of_slashes_alone_has_no_name() -> None:
    assert node_base_name(("/",)) == ""
    assert node_base_name(()) == ""
    assert node_base_name(("robot", "/")) == "robot"
    assert node_base_name(("/robot/", "//base//")) == "base"


def test_plain_values_before_a_node_do_not_end_the_search() -> None:
    text = f"""version: 3
robot:
  rate: 50
  controller_manager:
    ros__parameters:
      diff_cont: {{type: {DIFF}}}
  diff_cont:
    ros__parameters: {{wheel_separation: 0.3}}
"""
    (config,) = read_controllers(text, "c.yaml")
    assert (config.name, config.wheel_separation) == ("diff_cont", 0.3)


def test_an_empty_ros__parameters_section_is_a_section_without_parameters() -> None:
    text = f"""controller_manager:
  ros__parameters:
diff_cont:
  ros__parameters:
    type: {DIFF}
    wheel_radius: 0.05
joint_state_broadcaster:
  ros__parameters:
"""
    (config,) = read_controllers(text, "c.yaml")
    assert (config.name, config.wheel_radius, config.update_rate) == ("diff_cont", 0.05, None)


def test_ros__parameters_that_is_not_a_mapping_is_named_by_its_whole_path() -> None:
    for read in (read_controllers, other_drive_controllers):
        with pytest.raises(ControllerConfigError) as caught:
            read("robot:\n  ns:\n    diff_cont:\n      ros__parameters: [1, 2]\n", "x.yaml")
        assert str(caught.value) == (
            "x.yaml: robot/ns/diff_cont: ros__parameters must be a mapping, got [1, 2]"
        )


def test_a_section_of_another_node_does_not_leak_into_the_controller() -> None:
    text = f"""controller_manager:
  ros__parameters:
    update_rate: 50
    diff_cont: {{type: {DIFF}}}
other_cont:
  ros__parameters: {{wheel_radius: 0.5, wheel_separation: 9.0}}
diff_cont:
  ros__parameters: {{wheel_separation: 0.3}}
"""
    (config,) = read_controllers(text, "c.yaml")
    assert (config.wheel_radius, config.wheel_separation) == (None, 0.3)


def test_a_section_named_by_slashes_alone_applies_to_every_node_as_a_wildcard() -> None:
    text = f"""/:
  ros__parameters: {{wheel_radius: 0.05}}
controller_manager:
  ros__parameters:
    diff_cont: {{type: {DIFF}}}
diff_cont:
  ros__parameters: {{wheel_separation: 0.3}}
"""
    (config,) = read_controllers(text, "c.yaml")
    assert (config.wheel_radius, config.wheel_separation) == (0.05, 0.3)


def test_a_controller_declared_by_two_managers_is_one_and_the_next_is_still_found() -> None:
    text = f"""/left/controller_manager:
  ros__parameters:
    diff_cont: {{type: {DIFF}}}
/right/controller_manager:
  ros__parameters:
    diff_cont: {{type: {DIFF}}}
    second: {{type: {DIFF}}}
diff_cont:
  ros__parameters: {{wheel_separation: 0.3}}
second:
  ros__parameters: {{wheel_separation: 0.5}}
"""
    configs = read_controllers(text, "c.yaml")
    assert [(c.name, c.wheel_separation) for c in configs] == [
        ("diff_cont", 0.3),
        ("second", 0.5),
    ]


def test_a_controller_typed_in_its_section_before_its_manager_is_found_once() -> None:
    text = f"""diff_cont:
  ros__parameters: {{type: {DIFF}, wheel_separation: 0.3}}
/ns/diff_cont:
  ros__parameters: {{type: {DIFF}, wheel_radius: 0.05}}
controller_manager:
  ros__parameters:
    update_rate: 50
    diff_cont: {{type: {DIFF}}}
"""
    (config,) = read_controllers(text, "c.yaml")
    assert (config.wheel_separation, config.wheel_radius) == (0.3, 0.05)


def test_a_controller_typed_in_its_own_section_is_a_ros2_one_of_its_file() -> None:
    # ROS 2 keeps a limit given without its has_*_limits flag; ROS 1 would drop it.
    text = f"diff_cont:\n  ros__parameters:\n    type: {DIFF}\n    linear.x.max_velocity: 0.5\n"
    (config,) = read_controllers(text, "own.yaml")
    assert (config.source, config.ros_version) == ("own.yaml", 2)
    assert config.linear.max_velocity == 0.5


def test_a_ros1_controller_names_its_file() -> None:
    text = f"base:\n  type: {DIFF}\n  left_wheel: l\n  right_wheel: r\n"
    (config,) = read_controllers(text, "ros1.yaml")
    assert (config.source, config.ros_version) == ("ros1.yaml", 1)


def test_a_ros1_controller_after_a_plain_value_and_a_ros2_section_is_found() -> None:
    text = f"""rate: 50
node:
  ros__parameters: {{a: 1}}
base:
  type: {DIFF}
  left_wheel: l
  right_wheel: r
"""
    (config,) = read_controllers(text, "c.yaml")
    assert (config.name, config.left_wheel_names) == ("base", ("l",))


def test_a_ros1_controller_keyed_by_a_slash_takes_its_namespace_s_name() -> None:
    text = (
        f"robot:\n  base:\n    /:\n      type: {DIFF}\n      left_wheel: l\n      right_wheel: r\n"
    )
    (config,) = read_controllers(text, "c.yaml")
    assert config.name == "base"
    other = "robot:\n  base:\n    /:\n      type: mecanum_drive_controller/MecanumDriveController\n"
    assert other_drive_controllers(other, "c.yaml") == [
        ("base", "mecanum_drive_controller/MecanumDriveController")
    ]


def test_the_arguments_a_file_uses_are_kept_in_order_once_each() -> None:
    text = f"""base:
  type: {DIFF}
  left_wheel: $(arg left)
  right_wheel: $(arg right)
  wheel_separation: $(arg sep)
  wheel_radius: $(arg sep)
"""
    (config,) = read_controllers(text, "c.yaml", {"left": "l", "right": "r", "sep": "0.3"})
    assert config.arguments == ("left", "right", "sep")
    assert (config.left_wheel_names, config.wheel_separation) == (("l",), 0.3)


def test_a_chained_reference_of_one_slash_is_followed_to_its_joint() -> None:
    text = f"""controller_manager:
  ros__parameters:
    pid_left: {{type: pid_controller/PidController}}
    diff_cont: {{type: {DIFF}}}
pid_left:
  ros__parameters: {{dof_names: [left_wheel_joint]}}
diff_cont:
  ros__parameters:
    left_wheel_names: [pid_left/left_wheel_joint]
    right_wheel_names: [right_wheel_joint]
"""
    (config,) = read_controllers(text, "c.yaml")
    assert config.left_wheel_names == ("left_wheel_joint",)
    assert config.right_wheel_names == ("right_wheel_joint",)
    assert config.warnings == (
        "wheel 'pid_left/left_wheel_joint' is the reference of the chained controller "
        "'pid_left': followed to joint 'left_wheel_joint'",
    )


# --- other drives and command controllers ------------------------------------------------------


def test_a_drive_is_named_by_its_class_not_by_any_namespace_of_its_type() -> None:
    text = """robot:
  state:
    type: JointStateController
  arm:
    type: base/drive_tools/JointTrajectoryController
controller_manager:
  ros__parameters:
    grip.type: "base::drive_tools::GripperController"
    arm.type: base/drive_tools/JointTrajectoryController
    wheels.type: "base::tools::MecanumController"
"""
    assert other_drive_controllers(text, "c.yaml") == [("wheels", "base::tools::MecanumController")]


def test_sections_written_twice_are_merged_as_ros_merges_them_everywhere(tmp_path: Path) -> None:
    path = tmp_path / "c.yaml"
    path.write_text(
        """controller_manager:
  ros__parameters:
    mecanum: {type: mecanum_drive_controller/MecanumDriveController}
left:
  ros__parameters:
    joints: [wheel_a]
controller_manager:
  ros__parameters:
    update_rate: 50
left:
  ros__parameters:
    interface_name: velocity
""",
        encoding="utf-8",
    )
    assert load_other_drive_controllers(path) == [
        ("mecanum", "mecanum_drive_controller/MecanumDriveController")
    ]
    assert load_command_controllers(path) == {"left": ("wheel_a",)}


# --- messages and bounds of a file ------------------------------------------------------------


def test_every_reader_names_the_file_of_a_malformed_section(tmp_path: Path) -> None:
    path = tmp_path / "bad.yaml"
    path.write_text("diff_cont:\n  ros__parameters: 3\n", encoding="utf-8")
    expected = f"{path}: diff_cont: ros__parameters must be a mapping, got 3"
    for read in (load_controllers, load_other_drive_controllers, load_command_controllers):
        with pytest.raises(ControllerConfigError) as caught:
            read(path)
        assert str(caught.value) == expected


def test_other_drives_name_the_file_of_malformed_yaml() -> None:
    with pytest.raises(ControllerConfigError) as caught:
        other_drive_controllers("a: [1\n", "bad.yaml")
    assert str(caught.value).startswith("bad.yaml: malformed YAML: ")


def test_aliases_are_refused_as_not_allowed_in_a_controllers_file() -> None:
    with pytest.raises(ControllerConfigError) as caught:
        read_controllers("a: &a [1]\nb: *a\n", "bomb.yaml")
    assert str(caught.value) == (
        "bomb.yaml: YAML aliases (*name) are not allowed in a controllers file, "
        "write each entry out (line 2, column 4)"
    )


def test_a_folder_is_refused_as_no_controllers_file(tmp_path: Path) -> None:
    folder = tmp_path / "folder.yaml"
    folder.mkdir()
    with pytest.raises(ControllerConfigError) as caught:
        load_controllers(folder)
    assert str(caught.value) == f"{folder}: is a directory, not a controllers file"


def test_a_file_swapped_for_a_fifo_after_its_check_is_refused(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    fifo = tmp_path / "fifo.yaml"
    os.mkfifo(fifo)
    # As if the file were a regular one when checked and a FIFO when opened.
    monkeypatch.setattr(controllers, "check_regular", lambda *args, **kwargs: None)
    with pytest.raises(ControllerConfigError) as caught:
        load_controllers(fifo)
    assert str(caught.value) == (
        f"{fifo}: not a regular file (a FIFO, socket or device), not a controllers file"
    )


def test_an_oversized_file_is_refused_without_reading_it_whole(tmp_path: Path) -> None:
    huge = tmp_path / "huge.yaml"
    with huge.open("wb") as stream:
        stream.truncate(16 * MAX_FILE_BYTES)  # sparse: no disk is used

    def refused() -> None:
        with pytest.raises(ControllerConfigError, match="larger than"):
            load_controllers(huge)

    _, peak = peak_bytes(refused)
    assert peak < 4 * MAX_FILE_BYTES


def test_choosing_among_controllers_of_two_files_names_both_files() -> None:
    one = read_controllers(f"a:\n  type: {DIFF}\n  left_wheel: l\n  right_wheel: r\n", "a.yaml")
    two = read_controllers(f"b:\n  type: {DIFF}\n  left_wheel: l\n  right_wheel: r\n", "b.yaml")
    with pytest.raises(ControllerConfigError) as caught:
        choose_controller([*two, *one])
    assert str(caught.value) == (
        "several diff-drive controllers in a.yaml, b.yaml: 'b', 'a'; "
        "choose one by name (controller=)"
    )
