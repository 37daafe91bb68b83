#!/usr/bin/env bash
# Mutation testing, one module at a time against its own tests only.
#
#   tools/mutation.sh                 # every module below
#   tools/mutation.sh reference sdf   # some of them
#
# "live" mutates the whole live package against every live test that runs without other
# processes (hours); "live-codecs" its message codecs, names and checks against their own tests;
# "live-nodes" the odometry and wheel-command nodes and the signal handling against their tests,
# "live-graph" the simulated robot, drive, follow and discovery, "live-transport" the DDS
# plumbing and message types. A live selection waits DIFFBOT_TEST_PATIENCE (5 s) for discovery
# or a message: a mutant that breaks a node makes every wait run out.
#
# Each module is mutated by mutmut (the `test` extra installs it) in a scratch copy of the
# checkout under .mutation/<module>/, so that a run never touches the working tree; a summary
# line per module (killed / all, and the kill rate) is printed at the end and the surviving
# mutants are listed in .mutation/<module>/survivors.txt (`mutmut show NAME` there prints one).
# MUTATION_CHILDREN (default 1) sets how many mutants run at once.
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
python=${PYTHON:-$root/.venv/bin/python}
children=${MUTATION_CHILDREN:-1}

# module name | files mutated (globs, space-separated) | its own tests
modules=(
  "live-codecs|diffbot/live/cdr.py diffbot/live/wire.py diffbot/live/names.py diffbot/live/messages.py diffbot/live/qos.py|tests/live/test_cdr.py tests/live/test_wire.py tests/live/test_names.py tests/live/test_messages.py tests/live/test_types.py"
  "live|diffbot/live/*|tests/live --deselect tests/live/test_flood.py --deselect tests/live/test_live_commands.py --deselect tests/live/test_ros2_interop.py"
  "live-nodes|diffbot/live/odometry.py diffbot/live/inverse_kinematics.py diffbot/live/signals.py|tests/live/test_odometry_node.py tests/live/test_ik_node.py tests/live/test_signals.py tests/live/test_loop.py::test_the_loop_in_one_process"
  "live-graph|diffbot/live/robot.py diffbot/live/drive.py diffbot/live/follow_drive.py diffbot/live/endpoints.py diffbot/live/discovery.py|tests/live --deselect tests/live/test_flood.py --deselect tests/live/test_live_commands.py --deselect tests/live/test_ros2_interop.py"
  "live-transport|diffbot/live/transport.py diffbot/live/participant.py diffbot/live/cyclone.py diffbot/live/types.py|tests/live --deselect tests/live/test_flood.py --deselect tests/live/test_live_commands.py --deselect tests/live/test_ros2_interop.py"
  "planning|diffbot/planning/*|tests/planning"
  "goals|diffbot/goals.py|tests/test_goals.py"
  "conditioning|diffbot/conditioning.py|tests/test_conditioning.py tests/test_conditioning_time_offset.py"
  "reference|diffbot/reference.py|tests/test_reference.py"
  "sdf|diffbot/urdf/sdf.py|tests/urdf/test_sdf.py tests/urdf/test_sdf_frames.py tests/urdf/test_sdf_joints.py"
  "controllers|diffbot/urdf/controllers.py|tests/urdf/test_controllers.py tests/urdf/test_controllers_sections.py"
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
  # A live mutant that makes a node spin instead of wait burns CPU until mutmut's limit, 15 times
  # the tests' own time by default: 3 times is ample for a mutant that is merely slower. A test
  # that hangs for a minute fails then, rather than at the limit. A live test waits
  # DIFFBOT_TEST_PATIENCE for discovery or a message.
  hang='' limits='' patience=20
  if [[ $name == live* ]]; then
    hang=', "--timeout=60", "--timeout-method=thread"'
    limits='timeout_multiplier = 3.0'
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
killed = s["killed"] + s.get("timeout", 0) + s.get("segfault", 0)
# The stats count every mutant in "total", run or not: a stopped run has fewer results.
checked = killed + s["survived"] + s.get("no_tests", 0) + s.get("suspicious", 0)
unrun = s["total"] - s.get("skipped", 0) - checked
rate = 100.0 * killed / checked if checked else 100.0
print(f"{name}: {killed}/{checked} killed ({rate:.1f} %), {s['survived']} survived, "
      f"{s.get('no_tests', 0)} without tests, {s.get('suspicious', 0)} suspicious"
      + (f", {unrun} not run (the run was stopped)" if unrun else ""))
PY
)")
done
printf '%s\n' "${summary[@]}"
