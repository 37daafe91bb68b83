"""Shell completion, as the README tells users to set it up, works with diffbot's command group
(which loads each command only when it is needed)."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

DIFFBOT = str(Path(sys.executable).with_name("diffbot"))


def run_completion(mode: str, words: str = "", cword: int = 0) -> subprocess.CompletedProcess[str]:
    """Run ``diffbot`` as a shell's completion script does, with ``_DIFFBOT_COMPLETE=mode``."""
    env = {**os.environ, "_DIFFBOT_COMPLETE": mode, "COMP_WORDS": words, "COMP_CWORD": str(cword)}
    return subprocess.run(
        [DIFFBOT], env=env, capture_output=True, text=True, timeout=60, check=False
    )


@pytest.mark.parametrize(
    ("shell", "registration"),
    [
        ("bash", "complete -o nosort -F _diffbot_completion diffbot"),
        ("zsh", "compdef _diffbot_completion diffbot"),
        ("fish", "complete --no-files --command diffbot"),
    ],
)
def test_source_mode_prints_a_script_that_registers_diffbot(shell: str, registration: str) -> None:
    done = run_completion(f"{shell}_source")
    assert done.returncode == 0, done.stderr
    assert registration in done.stdout
    assert done.stderr == ""


@pytest.mark.skipif(shutil.which("bash") is None, reason="needs bash")
def test_the_bash_setup_the_readme_gives_completes_command_names() -> None:
    session = (
        'eval "$(_DIFFBOT_COMPLETE=bash_source diffbot)"; '
        "COMP_WORDS=(diffbot si); COMP_CWORD=1; _diffbot_completion diffbot; "
        'printf "%s\\n" "${COMPREPLY[@]}"'
    )
    env = {**os.environ, "PATH": f"{Path(DIFFBOT).parent}{os.pathsep}{os.environ.get('PATH', '')}"}
    done = subprocess.run(
        ["bash", "-c", session], env=env, capture_output=True, text=True, timeout=60, check=False
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines() == ["simulate"]


def test_bash_completes_command_names_from_the_command_table() -> None:
    done = run_completion("bash_complete", "diffbot si", 1)
    assert done.stdout.splitlines() == ["plain,simulate"]


def test_bash_completes_the_choices_of_an_option() -> None:
    done = run_completion("bash_complete", "diffbot plan --format ", 3)
    assert done.stdout.splitlines() == [
        "plain,table",
        "plain,json",
        "plain,csv",
        "plain,twist",
        "plain,wheels",
        "plain,ros2",
    ]
