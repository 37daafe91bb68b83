#!/usr/bin/env bash
# Mutation testing, one module at a time against its own tests only.
#
#   tools/mutation.sh                 # every module below
#   tools/mutation.sh reference sdf   # some of them
#
# "live" mutates the whole live package against every live test that runs without other
# processes (hours); the other live selections each mutate some of its modules against their
# own tests: "live-codecs" the message codecs, names and checks; "live-nodes" the odometry
# (wheels and open loop) and wheel-command nodes and the signal handling; "live-graph" the
# simulated robot, drive, follow, the endpoints and the discovery configuration;
# "live-transport" the DDS plumbing, its configuration and the message types. A live selection
# waits DIFFBOT_TEST_PATIENCE (5 s) for discovery
# or a message: a mutant that breaks a node makes every wait run out.
#
# Each module is mutated by mutmut (the `test` extra installs it) in a scratch copy of the
# checkout under .mutation/<module>/, so that a run never touches the working tree; a summary
# line per module (killed / all, and the kill rate) is printed at the end and the surviving
# mutants are listed in .mutation/<module>/survivors.txt (`mutmut show NAME` there prints one).
# MUTATION_CHILDREN (default 1) sets how many mutants run at once. A mutant stopped at mutmut's
# time bound is counted as timed out, not as killed: tools/mutation_recheck.py runs them (or a
# seeded sample) again without the bound and says which fail, hang or pass.
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
python=${PYTHON:-$root/.venv/bin/python}
children=${MUTATION_CHILDREN:-1}

# module name | files mutated (globs, space-separated) | its own tests
modules=(
  "live-codecs|diffbot/live/cdr.py diffbot/live/wire.py diffbot/live/names.py diffbot/live/messages.py diffbot/live/qos.py|tests/live/test_cdr.py tests/live/test_wire.py tests/live/test_names.py tests/live/test_messages.py tests/live/test_types.py tests/live/test_qos.py"
  "live|diffbot/live/*|tests/live --deselect tests/live/test_flood.py --deselect tests/live/test_live_commands.py --deselect tests/live/test_ros2_interop.py"
  "live-nodes|diffbot/live/odometry.py diffbot/live/open_loop_node.py diffbot/live/held_commands.py diffbot/live/twist_subscriptions.py diffbot/live/inverse_kinematics.py diffbot/live/signals.py|tests/live/test_odometry_node.py tests/live/test_open_loop_node.py tests/live/test_held_commands.py tests/live/test_ik_node.py tests/live/test_signals.py tests/live/test_loop.py::test_the_loop_in_one_process"
  "live-graph|diffbot/live/robot.py diffbot/live/drive.py diffbot/live/follow_drive.py diffbot/live/endpoints.py diffbot/live/discovery.py|tests/live/test_robot_node.py tests/live/test_drive.py tests/live/test_follow_drive.py tests/live/test_transport.py tests/live/test_keyhash.py tests/live/test_participant.py tests/live/test_loop.py::test_the_loop_in_one_process"
  "live-transport|diffbot/live/transport.py diffbot/live/participant.py diffbot/live/cyclone.py diffbot/live/types.py|tests/live/test_transport.py tests/live/test_participant.py tests/live/test_keyhash.py tests/live/test_types.py tests/live/test_discovery.py"
  "planning|diffbot/planning/*|tests/planning"
  "goals|diffbot/goals.py|tests/test_goals.py"
  "conditioning|diffbot/conditioning.py|tests/test_conditioning.py tests/test_conditioning_time_offset.py"
  "reference|diffbot/reference.py|tests/test_reference.py"
  "sdf|diffbot/urdf/sdf.py diffbot/urdf/sdf_frames.py|tests/urdf/test_sdf.py tests/urdf/test_sdf_frames.py tests/urdf/test_sdf_joints.py tests/urdf/test_sdf_includes.py"
  "controllers|diffbot/urdf/controllers.py|tests/urdf/test_controllers.py tests/urdf/test_controllers_sections.py"
  "include-glob|diffbot/urdf/include_glob.py|tests/urdf/test_include_glob.py"
)

wanted=("$@")
summary=()
for entry in "${modules[@]}"; do
  IFS='|' read -r name glob tests <<<"$entry"
  if [ ${#wanted[@]} -gt 0 ] && [[ ! " ${wanted[*]} " == *" $name "* ]]; then
    continue
  fi
  work=$root/.mutation/$name
  rm -rf "$work"
  mkdir -p "$work"
  cp -r "$root/diffbot" "$root/tests" "$root/pyproject.toml" "$work/"
  find "$work" -name __pycache__ -prune -exec rm -rf {} +
  # The module's own tests only, in mutmut's own process (-n 0: no test workers).
  # Under the trampolines every call is slower, the more so on a busy machine: no deadlines;
  # examples drawn the same on every run and no example database, so that runs repeat.
  cat >>"$work/tests/conftest.py" <<'PY'


from hypothesis import settings as _settings

_settings.register_profile("mutation", deadline=None, derandomize=True, database=None)
_settings.load_profile("mutation")
PY
  # mutmut stops a mutant at (the tests' recorded time + timeout_constant) x timeout_multiplier
  # of wall time. A live test's recorded time leaves out most of DDS's start and discovery, so
  # an unchanged node can run past a bound of a few seconds and a mutant its tests pass would
  # count as timed out: 30 s more covers that. A test that hangs fails after a minute
  # (pytest-timeout), before the bound. A live test waits DIFFBOT_TEST_PATIENCE for discovery or
  # a message.
  hang='' limits='' patience=20
  if [[ $name == live* ]]; then
    hang=', "--timeout=60", "--timeout-method=thread"'
    limits=$'timeout_multiplier = 3.0\ntimeout_constant = 30.0'
    patience=5
  fi
  selection=$("$python" -c 'import json, shlex, sys; print(json.dumps(shlex.split(sys.argv[1])))' "$tests")
  mutated=$("$python" -c 'import json, sys; print(json.dumps(sys.argv[1].split()))' "$glob")
  cat >>"$work/pyproject.toml" <<TOML

[tool.mutmut]
source_paths = ["diffbot"]
only_mutate = $mutated
pytest_add_cli_args = ["-p", "no:cacheprovider", "-p", "no:randomly", "-n", "0", "-x", "-q"$hang]
pytest_add_cli_args_test_selection = $selection
use_git_change_detection = false
$limits
TOML
  (cd "$work" && DIFFBOT_TEST_PATIENCE=$patience "$python" -m mutmut run --max-children "$children" >run.log 2>&1) || true
  (cd "$work" && "$python" -m mutmut export-cicd-stats >/dev/null 2>&1 || true)
  (cd "$work" && "$python" -m mutmut results >survivors.txt 2>&1 || true)
  summary+=("$("$python" - "$name" "$work/mutants/mutmut-cicd-stats.json" <<'PY'
import json, sys
name, path = sys.argv[1], sys.argv[2]
try:
    s = json.load(open(path))
except OSError:
    print(f"{name}: no result (see .mutation/{name}/run.log)")
    raise SystemExit
killed = s["killed"] + s.get("segfault", 0)
# A mutant stopped at the time bound is not known to be caught: it may be a slow survivor.
# tools/mutation_recheck.py runs them again without the bound.
timeout = s.get("timeout", 0)
# The stats count every mutant in "total", run or not: a stopped run has fewer results.
checked = killed + timeout + s["survived"] + s.get("no_tests", 0) + s.get("suspicious", 0)
unrun = s["total"] - s.get("skipped", 0) - checked
rate = 100.0 * killed / checked if checked else 100.0
print(f"{name}: {killed}/{checked} killed ({rate:.1f} %), {timeout} timed out, "
      f"{s['survived']} survived, "
      f"{s.get('no_tests', 0)} without tests, {s.get('suspicious', 0)} suspicious"
      + (f", {unrun} not run (the run was stopped)" if unrun else ""))
PY
)")
done
printf '%s\n' "${summary[@]}"
