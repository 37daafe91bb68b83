"""The command line's entry point: ``diffbot`` and ``python -m diffbot``.

Its first step holds the signals that end a run (:func:`diffbot.signal_handlers.hold`), before
the command line's modules load: a Ctrl-C, SIGTERM or SIGHUP that comes meanwhile is acted on
by the command as one that comes later would be (a node ends cleanly with exit code 0, another
command aborts), not as a traceback from the middle of an import.
"""

from diffbot import signal_handlers


def run() -> None:
    """Hold the ending signals, then run one command; the process ends with it."""
    signal_handlers.hold()
    from diffbot.cli import run as command_line

    command_line()


if __name__ == "__main__":
    run()
