"""The result of the compiled paths: :class:`SolveResult`, a dict with attribute access."""

__all__ = ["SolveResult"]


class SolveResult(dict):
    """Result of :func:`mbm.solve` / :func:`mbm.solve_batch`: a dict with attribute access,
    like scipy's ``OptimizeResult`` (not used here to keep ``import mbm`` free of
    ``scipy.optimize``)."""

    def __getattr__(self, name):
        try:
            return self[name]
        except KeyError:
            raise AttributeError(name) from None

    def __repr__(self):
        return "SolveResult(" + ", ".join(f"{k}={v!r}" for k, v in self.items()) + ")"
