"""Progress on long work (figures, dataset simulation, HIL runs, diagnosis): a tqdm bar, or a
live status line, on stderr while stderr is a terminal. Nothing at all otherwise (a pipe, a log
file, a test's capture) or under --quiet, so that what a program reads is the result alone."""

from __future__ import annotations

import sys

from tqdm import tqdm


def shown(quiet: bool = False) -> bool:
    """Whether progress is drawn: not asked to be quiet, and stderr is a terminal."""
    return not quiet and sys.stderr.isatty()


class Progress:
    """A bar over `total` units (steps, runs, figures), or with total None a status line that
    says what is being done and for how long. A context manager: the line is cleared on exit."""

    def __init__(self, desc: str, total: int | None = None, unit: str = "it", quiet: bool = False):
        self._bar = tqdm(
            total=total,
            desc=desc,
            unit=unit,
            file=sys.stderr,
            disable=not shown(quiet),
            leave=False,
            dynamic_ncols=True,
            bar_format=None if total is not None else "{desc} [{elapsed}]",
        )

    def __enter__(self) -> Progress:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        self._bar.close()

    def to(self, done: int, note: str | None = None) -> None:
        """Units done so far (absolute) and, if given, what is being worked on."""
        if note is not None:
            self._bar.set_postfix_str(note, refresh=False)
        self._bar.update(done - self._bar.n)

    def status(self, msg: str) -> None:
        """The status line's text (what the work is doing now)."""
        self._bar.set_description_str(msg)
