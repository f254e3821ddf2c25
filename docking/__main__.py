"""``python -m docking``: the command line (:mod:`docking.study.cli`)."""

if __name__ == "__main__":
    import atexit
    import os
    import signal
    import sys

    from docking import _PROG, _take_ctrl_c

    # Ctrl-C while the command's modules are imported: one line, 130 (the package did this
    # already under ``python -m docking``; ``runpy.run_module`` comes here without it).
    ctrl_c = _take_ctrl_c()
    from docking.glenv import RenderingUnavailable, check_gl_backend

    try:  # before docking.study.cli imports MuJoCo, whose own failure is a traceback
        check_gl_backend()
    except RenderingUnavailable as exc:
        print(f"{_PROG}: error: {exc}", file=sys.stderr)
        raise SystemExit(1) from None

    from docking.study.cli import main

    # A command is interrupted by KeyboardInterrupt, so that a sweep closes its cluster on the
    # way out; main says so in one line and returns 130.
    if ctrl_c:
        signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        status = main()
        sys.stdout.flush()
    except BrokenPipeError:  # the reader of the output left (``... --help | head``)
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        status = 141  # as a shell reports SIGPIPE
    if status == 130:
        # main caught a KeyboardInterrupt and said so in one line. CPython 3.11 can still hold
        # it unhandled (seen under load, with the interrupt met inside code that namedtuple
        # evaluates while dm_control is imported) and then ends ``python -m`` by SIGINT after
        # finalising, whatever the status. So end here: atexit handlers run, then status 130.
        sys.stderr.flush()
        atexit._run_exitfuncs()
        os._exit(130)
    raise SystemExit(status)
