"""The run statuses: one table of (code, name, flag, message) for every path.

A run of the compiled loop (:mod:`mbm.core.loop`) ends with one of these codes in its
record's ``status``; :func:`mbm.solve`, :class:`mbm.Integrator`, :func:`mbm.solve_batch`
report it as ``status`` with its ``message``, :class:`mbm.MBM` turns a failure into
solve_ivp's message, and :func:`mbm.sweep` writes it as a CF flag variable (its
``flag_meanings`` are the flags here).  :data:`STATUS_PAUSED` is not a result: a call
stopped at its window budget, a full window store or a regime switch, and the caller
resumes the run.
"""

__all__ = [
    "STATUS_TABLE",
    "STATUS_OK",
    "STATUS_TOO_SMALL",
    "STATUS_ANCHOR",
    "STATUS_NONFINITE",
    "STATUS_MAX_WINDOWS",
    "STATUS_INTERRUPTED",
    "STATUS_EVENT",
    "STATUS_CROWDED",
    "STATUS_PAUSED",
    "STATUS_NAMES",
    "STATUS_FLAGS",
    "STATUS_MESSAGES",
    "status_message",
]

#: (code, name, CF flag word, message) of every status a run reports.
STATUS_TABLE = (
    (0, "OK", "ok", "The solver successfully reached the end of the integration interval."),
    (1, "TOO_SMALL", "window_too_small",
     "Required window is below the spacing of floating point numbers (the tolerance cannot be met)."),
    (2, "ANCHOR", "anchor_outside_domain",
     "The approximant cannot be anchored at the state reached (outside its domain)."),
    (3, "NONFINITE", "non_finite_state", "The approximant produced a non-finite state (outside its domain)."),
    (4, "MAX_WINDOWS", "max_windows_reached",
     "The run took max_windows windows without reaching the end of the interval (raise max_windows for a "
     "longer run)."),
    (5, "INTERRUPTED", "interrupted", "Interrupted (KeyboardInterrupt) before the end of the interval."),
    (6, "EVENT", "terminal_event", "A termination event occurred."),
    (7, "CROWDED", "too_many_crossings",
     "A window held more crossings of one event level than the event watch takes (WINDOW_CROSSINGS); pass a "
     "smaller max_step."),
)

STATUS_OK = 0
STATUS_TOO_SMALL = 1
STATUS_ANCHOR = 2
STATUS_NONFINITE = 3
STATUS_MAX_WINDOWS = 4
STATUS_INTERRUPTED = 5
# A terminal event of mbm.events.compiled stopped the run (a success, as scipy's status 1).
STATUS_EVENT = 6
# A window of an event watch held more crossings of one level than it takes.
STATUS_CROWDED = 7
# Not a result: the call stopped at its window budget, a full window store or a regime
# switch, and the caller resumes the run (the caller's loop is where Ctrl-C is honoured).
STATUS_PAUSED = -1

#: code -> name, CF flag word, message.
STATUS_NAMES = {code: name for code, name, _, _ in STATUS_TABLE}
STATUS_FLAGS = {code: flag for code, _, flag, _ in STATUS_TABLE}
STATUS_MESSAGES = {code: message for code, _, _, message in STATUS_TABLE}

# The named codes are the table's, so the two cannot drift apart.
assert {c: n for c, n in STATUS_NAMES.items()} == {
    globals()["STATUS_" + n]: n for n in STATUS_NAMES.values()}


def status_message(code):
    """The message of a status code.

    Parameters
    ----------
    code : int
        A run's ``status`` (:data:`STATUS_TABLE`).

    Returns
    -------
    str

    Raises
    ------
    ValueError
        For a code that is not in the table.
    """
    try:
        return STATUS_MESSAGES[int(code)]
    except KeyError:
        raise ValueError(f"status must be one of {sorted(STATUS_MESSAGES)}, got {code!r}") from None
