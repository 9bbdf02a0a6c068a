"""Studies of many designs: sweeps, tolerance Monte Carlo, optimisation (issue 28)."""

__all__: list[str] = []
