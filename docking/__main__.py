"""``python -m docking``: the command line (:mod:`docking.cli`)."""

if __name__ == "__main__":
    from docking.cli import main

    raise SystemExit(main())
