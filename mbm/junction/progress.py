"""Progress bars, on tqdm.

:class:`Progress` and :func:`progress`, for the command line (studies, benchmarks), draw
one tqdm line on stderr, and nothing at all when stderr is not a terminal (pipes, log
files, pytest's capture), so that captured output stays clean.  :func:`progress_bar`,
for the library's ``progress=True``, is drawn wherever it is asked for: a widget in a
notebook (``tqdm.auto``), a line on stderr in a terminal or a log.
"""

import sys

from tqdm import tqdm
from tqdm.auto import tqdm as tqdm_auto

__all__ = ["Progress", "progress", "progress_bar"]

# Width of the bar in characters: fits an 80-column terminal with label and counts.
BAR_WIDTH = 28
# Minimum seconds between redraws: a sweep of thousands of cheap steps would otherwise
# spend more time writing to the terminal than computing.
MIN_REDRAW_S = 0.1
# The line drawn: ``label [#####-----] i/total  elapsed``.
BAR_FORMAT = "{desc} [{bar:%d}] {n_fmt}/{total_fmt} {elapsed}" % BAR_WIDTH


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
        self._bar = (tqdm(total=self.total, desc=self.label, file=self.stream, ascii="-#",
                          bar_format=BAR_FORMAT, mininterval=MIN_REDRAW_S, dynamic_ncols=False,
                          leave=True)
                     if self.enabled else None)

    def update(self, n=1):
        """Advance by ``n`` steps and redraw (at most every :data:`MIN_REDRAW_S`).

        Parameters
        ----------
        n : int, optional
            Steps done (default 1).
        """
        self.count += int(n)
        if self._bar is not None:
            self._bar.update(int(n))

    def message(self, text, stream=None):
        """Print ``text`` as a line of its own without breaking the bar.

        With the bar drawn on ``stream`` (default: the bar's stream) the bar line is
        cleared, ``text`` printed and the bar redrawn under it (``tqdm.write``);
        otherwise ``text`` is just printed to ``stream`` (nothing when that is None and
        the bar is off).

        Parameters
        ----------
        text : str
            The line to print.
        stream : file-like, optional
            Where to print it (default the bar's stream).
        """
        target = self.stream if stream is None else stream
        if self._bar is not None and target is self.stream:
            self._bar.write(str(text), file=target)
        elif stream is not None:
            print(text, file=stream, flush=True)

    def close(self):
        """Finish the line (a newline), if anything was drawn."""
        if self._bar is not None:
            self._bar.close()
            self._bar = None
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


def progress_bar(total, label, unit="it"):
    """The bar of a library call's ``progress=True``: ``tqdm.auto`` over ``total`` steps.

    A notebook widget under Jupyter, else a line on stderr, terminal or not (a log
    keeps it), redrawn at most every :data:`MIN_REDRAW_S`.

    Parameters
    ----------
    total : int
        Number of steps.
    label : str
        Text in front of the bar.
    unit : str, optional
        The name of a step (default ``"it"``).

    Returns
    -------
    tqdm.auto.tqdm
        Call ``.update(n)`` and ``.close()`` (or use it as a context manager).
    """
    return tqdm_auto(total=int(total), desc=str(label), unit=unit, file=sys.stderr,
                     mininterval=MIN_REDRAW_S)
