"""``python -m docking``: the command line (:mod:`docking.cli`)."""

if __name__ == "__main__":
    import os
    import signal
    import sys

    def _interrupted(signum, frame):  # Ctrl-C while the package is imported: nothing to undo
        print("python -m docking: interrupted", file=sys.stderr, flush=True)
        os._exit(130)

    # Not KeyboardInterrupt while importing: an extension module's initialisation turns it
    # into an ImportError, or Python exits by SIGINT after it was handled.
    signal.signal(signal.SIGINT, _interrupted)
    from docking.glenv import RenderingUnavailable, check_gl_backend

    try:  # before docking.cli imports MuJoCo, whose own failure is a traceback
        check_gl_backend()
    except RenderingUnavailable as exc:
        print(f"python -m docking: error: {exc}", file=sys.stderr)
        raise SystemExit(1) from None

    from docking.cli import main

    # A command is interrupted by KeyboardInterrupt, so that a sweep closes its cluster on the
    # way out; main says so in one line and returns 130.
    signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        status = main()
        sys.stdout.flush()
    except BrokenPipeError:  # the reader of the output left (``... --help | head``)
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        status = 141  # as a shell reports SIGPIPE
    raise SystemExit(status)
