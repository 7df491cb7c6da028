"""Time-integration settings shared by the tread-block simulators.

Every simulator of :mod:`friction_model.dynamics` takes ``solver: SolverOptions | None``;
a field left at None takes the model's default (:data:`RIGID_SOLVER`,
:data:`EULER_BERNOULLI_SOLVER`, :data:`TIMOSHENKO_SOLVER`), so that
``SolverOptions(rtol=1e-8)`` tightens one tolerance and keeps the rest::

    simulate_sdof(params, ..., solver=SolverOptions(rtol=1e-8, atol=1e-11))

Each model checks the options against its own :class:`SolverRules` (the implicit methods
it supports and the tolerance ranges its state scaling allows) before integrating.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

from tir_common.validate import check_positive, check_range

__all__ = [
    "EULER_BERNOULLI_SOLVER",
    "RIGID_SOLVER",
    "TIMOSHENKO_SOLVER",
    "SolverOptions",
    "SolverRules",
]


@dataclass(frozen=True)
class SolverOptions:
    """Method, tolerances and largest step of an implicit time integration.

    Parameters
    ----------
    method : str, optional
        Implicit solver of :mod:`scipy.integrate`: ``"LSODA"``, ``"Radau"`` or ``"BDF"``
        (which of them a model accepts: its :class:`SolverRules`).
    rtol : float, optional
        Relative tolerance, > 0.
    atol : float, optional
        Absolute tolerance, > 0, in the units of the model's states (rad and rad/s for the
        rigid models, m for the Euler-Bernoulli modal coordinates, scaled states for the
        Timoshenko model: see each simulator).
    max_step_s : float, optional
        Largest solver step, s, > 0 (set it below the shortest feature of the inputs).

    Examples
    --------
    >>> RIGID_SOLVER.default.merged(SolverOptions(rtol=1e-8))
    SolverOptions(method='LSODA', rtol=1e-08, atol=1e-09, max_step_s=None)
    """

    method: str | None = None
    rtol: float | None = None
    atol: float | None = None
    max_step_s: float | None = None

    def __post_init__(self) -> None:
        if self.method is not None and not isinstance(self.method, str):
            raise TypeError(
                f"method must be a str, got {type(self.method).__name__}: {self.method!r}"
            )
        for name in ("rtol", "atol", "max_step_s"):
            value = getattr(self, name)
            if value is not None:
                object.__setattr__(self, name, check_positive(name, value))

    def merged(self, given: SolverOptions | None) -> SolverOptions:
        """These options with every field that ``given`` sets replaced by its value."""
        if given is None:
            return self
        if not isinstance(given, SolverOptions):
            raise TypeError(f"solver must be a SolverOptions, got {type(given).__name__}")
        changes = {
            name: getattr(given, name)
            for name in ("method", "rtol", "atol", "max_step_s")
            if getattr(given, name) is not None
        }
        return replace(self, **changes)

    def solve_ivp_options(self) -> dict[str, Any]:
        """Keywords ``method``, ``rtol``, ``atol`` (``max_step``) of ``solve_ivp``."""
        opts: dict[str, Any] = {"method": self.method, "rtol": self.rtol, "atol": self.atol}
        if self.max_step_s is not None:
            opts["max_step"] = self.max_step_s
        return opts


@dataclass(frozen=True)
class SolverRules:
    """What one model accepts: its methods, tolerance ranges and default options.

    Parameters
    ----------
    methods : tuple of str
        Implicit methods the model supports.
    rtol_range, atol_range : (float, float)
        Closed ranges of the tolerances.
    default : SolverOptions
        The model's options (every field but ``max_step_s`` set).
    """

    methods: tuple[str, ...]
    rtol_range: tuple[float, float]
    atol_range: tuple[float, float]
    default: SolverOptions

    def resolve(self, solver: SolverOptions | None, *, t_end_s: float) -> SolverOptions:
        """The default merged with ``solver``, checked (ValueError naming the option).

        ``max_step_s`` must lie in [1e-12 s, ``t_end_s``].
        """
        opts = self.default.merged(solver)
        if opts.method not in self.methods:
            raise ValueError(
                f"method must be one of {self.methods} (implicit), got method={opts.method!r}"
            )
        check_range("rtol", opts.rtol, *self.rtol_range)
        check_range("atol", opts.atol, *self.atol_range)
        if opts.max_step_s is not None:
            check_range("max_step_s", opts.max_step_s, 1e-12, t_end_s, unit="s")
        return opts


_SCIPY_IMPLICIT = ("Radau", "BDF", "LSODA")
#: Rigid SDOF element and siped block (:func:`~friction_model.dynamics.simulate_sdof`,
#: :func:`~friction_model.dynamics.simulate_block_dynamics`).
RIGID_SOLVER = SolverRules(
    methods=_SCIPY_IMPLICIT,
    rtol_range=(1e-13, 1e-2),
    atol_range=(1e-16, 1e-2),
    default=SolverOptions(method="LSODA", rtol=1e-6, atol=1e-9),
)
#: Modal Euler-Bernoulli beam (:func:`~friction_model.dynamics.simulate_euler_bernoulli`).
EULER_BERNOULLI_SOLVER = SolverRules(
    methods=_SCIPY_IMPLICIT,
    rtol_range=(1e-13, 1e-2),
    atol_range=(1e-18, 1e-2),
    default=SolverOptions(method="LSODA", rtol=1e-6, atol=1e-12),
)
#: Timoshenko element (:func:`~friction_model.dynamics.simulate_timoshenko`): stepped with
#: its analytic sparse Jacobian, so only the methods that take one.
TIMOSHENKO_SOLVER = SolverRules(
    methods=("BDF", "Radau"),
    rtol_range=(1e-10, 0.1),
    atol_range=(1e-14, 0.01),
    default=SolverOptions(method="BDF", rtol=1e-5, atol=1e-7),
)
