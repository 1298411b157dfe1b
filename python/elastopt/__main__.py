"""`python -m elastopt ARGS...` and the `elastopt` command pip installs: the elastopt CLI
(run, bench, list, help, check, ...) that matches the package's library.

The CLI is the compiled program installed inside the package (pip), or the build tree's
cli/elastopt when the package runs from the source tree (see elastopt.cli_path()). It
replaces the Python process (exec), so its exit status, output and signals are the
program's own. Optimizers registered from Python live in this process only and are not
seen by the program: benchmark them with elastopt.run_bench instead.
"""
from __future__ import annotations

import os
import sys
from typing import NoReturn, Sequence


def main(argv: Sequence[str] | None = None) -> NoReturn:
    """Exec the elastopt CLI with argv (default sys.argv[1:]); never returns. Exit
    status 127 with a message on stderr if the program cannot be found."""
    from ._ffi import cli_path   # loads the library: the program beside the one in use
    args = list(sys.argv[1:] if argv is None else argv)
    try:
        exe = cli_path()
    except FileNotFoundError as e:
        print(e, file=sys.stderr)
        raise SystemExit(127)
    sys.stdout.flush()
    sys.stderr.flush()
    os.execv(str(exe), ["elastopt", *args])


if __name__ == "__main__":
    main()
