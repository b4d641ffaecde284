"""A small progress bar for long command-line runs (studies, sweeps, benchmarks).

Writes one self-overwriting line to stderr, and nothing at all when stderr is not a
terminal (pipes, log files, pytest's capture), so that captured output stays clean.
No external dependency.
"""

import sys
import time

__all__ = ["Progress", "progress"]

# Width of the bar in characters: fits an 80-column terminal with label and counts.
BAR_WIDTH = 28
# Minimum seconds between redraws: a sweep of thousands of cheap steps would otherwise
# spend more time writing to the terminal than computing.
MIN_REDRAW_S = 0.1


class Progress:
    """Progress of ``total`` steps, drawn as ``label [#####-----] i/total  elapsed``.

    Parameters
    ----------
    total : int
        Number of steps (>= 0).
    label : str, optional
        Text in front of the bar.
    stream : file-like, optional
        Where to draw; default ``sys.stderr`` (looked up at construction).
    enabled : bool, optional
        Force drawing on or off; default: on exactly when ``stream.isatty()``.

    Examples
    --------
    >>> with Progress(3, "sweep", enabled=False) as bar:
    ...     for _ in range(3):
    ...         bar.update()
    >>> bar.count
    3
    """

    def __init__(self, total, label="", stream=None, enabled=None):
        self.total = max(int(total), 0)
        self.label = str(label)
        self.stream = sys.stderr if stream is None else stream
        if enabled is None:
            isatty = getattr(self.stream, "isatty", None)
            try:
                enabled = bool(isatty()) if isatty is not None else False
            except (ValueError, OSError):  # a closed stream is not a terminal
                enabled = False
        self.enabled = bool(enabled)
        self.count = 0
        self._t0 = time.perf_counter()
        self._last = -float("inf")

    def _line(self):
        frac = self.count / self.total if self.total else 1.0
        filled = int(round(BAR_WIDTH * min(frac, 1.0)))
        bar = "#" * filled + "-" * (BAR_WIDTH - filled)
        elapsed = time.perf_counter() - self._t0
        return f"\r{self.label} [{bar}] {self.count}/{self.total} {elapsed:6.1f} s"

    def update(self, n=1):
        """Advance by ``n`` steps and redraw (at most every :data:`MIN_REDRAW_S`)."""
        self.count += int(n)
        if not self.enabled:
            return
        now = time.perf_counter()
        if now - self._last >= MIN_REDRAW_S or self.count >= self.total:
            self._last = now
            self.stream.write(self._line())
            self.stream.flush()

    def message(self, text, stream=None):
        """Print ``text`` as a line of its own without breaking the bar.

        With the bar drawn on ``stream`` (default: the bar's stream) the bar line is
        cleared, ``text`` printed and the bar redrawn under it; otherwise ``text`` is
        just printed to ``stream`` (nothing when that is None and the bar is off).
        """
        target = self.stream if stream is None else stream
        if self.enabled and target is self.stream:
            width = len(self._line()) - 1
            target.write("\r" + " " * width + "\r" + str(text) + "\n" + self._line())
            target.flush()
        elif stream is not None:
            print(text, file=stream, flush=True)

    def close(self):
        """Finish the line (a newline), if anything was drawn."""
        if self.enabled:
            self.stream.write(self._line() + "\n")
            self.stream.flush()
            self.enabled = False

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False


def progress(iterable, label="", total=None, stream=None, enabled=None):
    """Yield the items of ``iterable`` while drawing a :class:`Progress` bar.

    Parameters
    ----------
    iterable : iterable
    label : str, optional
    total : int, optional
        Default ``len(iterable)``.
    stream, enabled
        As for :class:`Progress`.

    Yields
    ------
    object
        The items of ``iterable``, unchanged.
    """
    if total is None:
        total = len(iterable)
    with Progress(total, label, stream=stream, enabled=enabled) as bar:
        for item in iterable:
            yield item
            bar.update()
