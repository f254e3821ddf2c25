"""``python -m docking``: the command line (:mod:`docking.study.cli`)."""

if __name__ == "__main__":
    import atexit
    import os
    import sys

    # Imports the standard library alone: the command's modules are imported by main, with
    # Ctrl-C one line and status 130 while they are (take_ctrl_c).
    from docking.study.cli import main, take_ctrl_c

    take_ctrl_c()
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
