"""The command line's entry point: ``diffbot`` and ``python -m diffbot``.

Its first step holds the signals that end a run (:func:`diffbot.signal_handlers.hold`), before
the command line's modules load: a Ctrl-C, SIGTERM or SIGHUP that comes meanwhile is acted on
once the command is known, as one that comes during the run is (Ctrl-C aborts with exit code
130, SIGTERM and SIGHUP end the run with 143 and 129), not raised in the middle of an import.
A node or a drive holds it through its setup too, and acts on it before the node is made; a
second signal meanwhile ends the process at once.
"""

from diffbot import signal_handlers


def run() -> None:
    """Hold the ending signals, then run one command; the process ends with it."""
    signal_handlers.hold()
    from diffbot.cli import run as command_line

    command_line()


if __name__ == "__main__":
    run()
