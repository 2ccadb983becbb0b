"""The abstract physical model: conserved variables, flux, Jacobian, wave speeds, source.

A model is *physics only*. It knows nothing of ghost cells, staggering, time steps or boundary
conditions. Its physics is written once, as module-level numba-compiled *pointwise* functions that
act on one state vector::

    flux_point(q, aux, params, out)        # out[:] = f(q)
    jacobian_point(q, aux, params, out)    # out[:, :] = df/dq (q)
    max_speed_point(q, aux, params) -> float   # max |eigenvalue of df/dq|
    source_point(q, aux, params, out)      # out[:] = s(q)     (only if has_source)
    admissible_point(q, aux, params) -> bool   # q in the admissible set (default: finite)

``q`` has shape ``(n_vars,)``, ``aux`` the per-point coefficients ``(n_aux,)`` (chute angle, bed
slope, ...), ``params`` the packed parameter vector of :meth:`Model.param_vector`. The compiled
Nessyahu–Tadmor kernel calls these functions directly; the array methods of :class:`Model`
(``flux``, ``flux_jacobian``, ...) are compiled loops over the same functions, so the reference path
and the compiled path share one copy of the physics.
"""

from __future__ import annotations

import dataclasses
from abc import ABC
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar, Protocol

import numpy as np
from numpy.typing import NDArray

from conslaw import pointwise
from conslaw.coefficient_loops import coefficients_2d_cells, corner_coefficients_cells
from conslaw.errors import ConfigError, unknown_name_message
from conslaw.kernelgen import generate

if TYPE_CHECKING:
    from conslaw.exact import ExactSolution
    from conslaw.exact2d import ExactSolution2D
    from conslaw.grid import Grid
    from conslaw.grid2d import Grid2D

Array = NDArray[np.float64]


class InitialData(Protocol):
    """What an exact solution reads of a scene's initial condition
    (:class:`conslaw.initial.InitialCondition`): its kind and options."""

    @property
    def kind(self) -> str: ...

    @property
    def options(self) -> Mapping[str, Any]: ...


def parameter(default: Any, meaning: str) -> Any:
    """A field of a model's ``Parameters`` dataclass with what it means: the symbol, unit and
    admissible range, in one sentence. The parameter reference (docs/parameters.md) is generated
    from these.

    Parameters
    ----------
    default
        The value a scene gets when it does not set the key.
    meaning
        One line for the reference table (markdown).
    """
    return dataclasses.field(default=default, metadata={"meaning": meaning})


@dataclasses.dataclass(frozen=True)
class NoParameters:
    """Parameter set of a model without parameters."""


class Model(ABC):
    """Abstract base of every physical model.

    Subclasses set the class attributes below and provide the pointwise kernels as
    ``staticmethod``-wrapped numba functions defined at module level (so they can be imported by
    the generated kernels). Registration (:mod:`conslaw.registry`) checks this contract.

    Attributes
    ----------
    name, description : str
        Registry name and a one-line description.
    variables : tuple of str
        Names of the conserved variables, in the order of the rows of ``q``.
    aux_names : tuple of str
        Names of the static per-point coefficients returned by :meth:`aux` (may be empty).
    reflect_signs : tuple of float
        Factor applied to each variable when it is mirrored at a reflective wall (momentum: -1).
    has_source : bool
        Whether the model has a source term (``source_point`` is then required).
    depth_index : int or None
        Row of the depth variable for models with dry states (front tracking, Lagrangian scheme).
    Parameters : dataclass type
        Frozen dataclass holding the physical parameters; it validates itself. Declare each
        field with :func:`parameter` so that the parameter reference documents it.
    """

    name: ClassVar[str]
    description: ClassVar[str]
    variables: ClassVar[tuple[str, ...]]
    #: What the variables, ``x`` and ``t`` are, for labelled output (``RunResult.to_xarray``):
    #: name -> long name. Values are in the scene's own units.
    long_names: ClassVar[Mapping[str, str]] = {"x": "position", "t": "time"}
    #: Whether the equations are in scaled, dimensionless variables (labelled output says so).
    dimensionless: ClassVar[bool] = False
    aux_names: ClassVar[tuple[str, ...]] = ()
    reflect_signs: ClassVar[tuple[float, ...]]
    #: Sign of every coefficient row under a mirror image (a slope is odd: -1); default all +1.
    aux_reflect_signs: ClassVar[tuple[float, ...] | None] = None
    has_source: ClassVar[bool] = False
    depth_index: ClassVar[int | None] = None
    #: Row of the momentum ``depth * velocity`` of a depth-averaged model (with ``depth_index``):
    #: its slope is then bounded so that the velocities at the quarter points stay within those
    #: of the cell and its neighbours.
    momentum_index: ClassVar[int | None] = None
    Parameters: ClassVar[type] = NoParameters

    flux_point: ClassVar[Callable[..., None]]
    jacobian_point: ClassVar[Callable[..., None]]
    max_speed_point: ClassVar[Callable[..., float]]
    source_point: ClassVar[Callable[..., None] | None] = None
    admissible_point: ClassVar[Callable[..., bool] | None] = None
    #: Optional ``balanced_source_point(q_left, q_right, aux_left, aux_right, dx, params, out)``:
    #: the source averaged over the staggered cell between two centres, replacing the
    #: quarter-point pair of eqs. (13)-(14) (a well-balanced pairing with the flux).
    balanced_source_point: ClassVar[Callable[..., None] | None] = None
    #: Optional ``correct_point(q, aux, params, dt)``: in-place pointwise correction of every
    #: new cell average after each step (dry cells, Coulomb stopping).
    correct_point: ClassVar[Callable[..., None] | None] = None
    #: Optional ``resistance_point(q, aux, params) -> float >= 0``: magnitude of a Coulomb-type
    #: resistance opposing the momentum (``momentum_index``); it can stop the flow but never
    #: accelerate or reverse it.
    resistance_point: ClassVar[Callable[..., float] | None] = None
    #: Optional ``coefficients_point(q, slope, aux, params)``: sets per-cell coefficients in
    #: ``aux`` (in place) from the cell's state and reconstructed slopes before the Jacobian of
    #: the predictor is evaluated (the Savage–Hutter earth-pressure coefficient).
    coefficients_point: ClassVar[Callable[..., None] | None] = None
    #: Optional ``interface_coefficients_point(left, right, aux_left, aux_right, params)``: sets,
    #: in place, the coefficients with which the fluxes at the two ends of one staggered cell are
    #: evaluated, from the mid-step states ``left`` and ``right`` there. Both fluxes of a cell
    #: then use one coefficient (the Savage–Hutter earth pressure of the cell: a switch between
    #: neighbours then exerts no force of its own, docs/design.md, "Earth pressure").
    interface_coefficients_point: ClassVar[Callable[..., None] | None] = None
    #: Optional ``rest_coefficients_point(low, high, params)``: for material at rest, whose
    #: dynamic coefficients its motion does not determine, sets (in place, from the static
    #: coefficients in both) the two ends of the range they may take (the Savage–Hutter earth
    #: pressure of a static mass lies anywhere between ``K_act`` and ``K_pass``). The NT scheme
    #: stops material that some continuous choice in that range, with the resistance, brings to
    #: rest within a step (docs/design.md, "Earth pressure").
    rest_coefficients_point: ClassVar[Callable[..., None] | None] = None
    #: ``(bed average, bed slope)`` rows of ``aux``: the depth variable is then reconstructed as
    #: the surface ``depth + bed`` (surface gradient method), its slope being
    #: ``slope(surface) - dx * bed slope``.
    surface_aux: ClassVar[tuple[int, int] | None] = None
    #: A two-dimensional model's y-direction functions, with the signatures of ``flux_point``,
    #: ``jacobian_point`` and ``max_speed_point``: the flux ``g(q)`` of ``q_t + f(q)_x + g(q)_y
    #: = s``, its Jacobian ``B = dg/dq`` and the largest ``|eigenvalue|`` of ``B``
    #: (docs/design.md, "Toward two dimensions"). None for a 1D model.
    flux_y_point: ClassVar[Callable[..., None] | None] = None
    #: A 2D model's factor of each variable in the mirror image across a y wall (the y
    #: momentum: -1); None: those across an x wall (:attr:`reflect_signs`).
    reflect_signs_y: ClassVar[tuple[float, ...] | None] = None
    jacobian_y_point: ClassVar[Callable[..., None] | None] = None
    max_speed_y_point: ClassVar[Callable[..., float] | None] = None
    #: A 2D model's ``balanced_source_point`` between two centres along y (spacing ``dy``).
    balanced_source_y_point: ClassVar[Callable[..., None] | None] = None
    #: A 2D model's row of the y momentum ``depth * y velocity`` (with ``depth_index``).
    momentum_y_index: ClassVar[int | None] = None
    #: A 2D model's ``(bed slope in y, bed twist)`` rows of ``aux`` besides :attr:`surface_aux`:
    #: the depth is then reconstructed as the surface minus the bed in both directions
    #: (docs/design.md, "Toward two dimensions").
    surface_aux_y: ClassVar[tuple[int, int] | None] = None
    #: How a 2D model's coefficients vary over the plane: ``"bed"`` (a bed from
    #: ``quarter_bed``, with :attr:`surface_aux` and :attr:`surface_aux_y`) or ``"along-x"``
    #: (:meth:`aux` of the arc length, the same in every row: a chute); ``""`` without
    #: coefficients; ``"field"`` (:meth:`aux_2d` at any map points: a terrain). The 2D scheme
    #: refuses a model with coefficients and none of these.
    aux_layout_2d: ClassVar[str] = ""
    #: A 2D model's rows of ``aux`` holding a surface gradient ``(b_x, b_y)``: its resistance
    #: then acts on the tangential momentum, of length ``(|m|^2 + (grad b . m)^2)^(1/2)`` for
    #: the map momentum ``m`` (:mod:`conslaw_models.savage_hutter_terrain`); None: ``|m|``.
    tangent_slope_rows: ClassVar[tuple[int, int] | None] = None
    #: Whether a cell whose values are all 0 and whose neighbours' are too stays so in a step
    #: (no flux, no source and no resistance at the empty state: no mass appears from nothing).
    #: The compiled 2D kernels then skip rows far from any material ("Cost that follows the
    #: flow", docs/design.md); a model with a source at the empty state (rain, a sink) must
    #: leave it False.
    empty_stays_empty: ClassVar[bool] = False
    #: Sign of every coefficient row in the mirror image across a y wall; None: all +1.
    aux_reflect_signs_y: ClassVar[tuple[float, ...] | None] = None
    #: Optional ``coefficients_2d_point(q, slope_x, slope_y, aux, params)``: a 2D model's
    #: ``coefficients_point``, from the slopes in x and in y (the earth-pressure coefficients of
    #: :mod:`conslaw_models.savage_hutter_2d`).
    coefficients_2d_point: ClassVar[Callable[..., None] | None] = None
    #: Optional ``corner_coefficients_point(a, b, c, d, aux, params)``: a 2D model's
    #: ``interface_coefficients_point``: sets the rows :attr:`varying_aux_rows` of ``aux`` (in
    #: place), with which every flux of a staggered cell is evaluated, from the mid-step states
    #: of its corner cells (lower left, lower right, upper left, upper right).
    corner_coefficients_point: ClassVar[Callable[..., None] | None] = None
    #: The rows of ``aux`` that ``coefficients_2d_point`` and ``corner_coefficients_point`` set.
    varying_aux_rows: ClassVar[tuple[int, ...]] = ()
    #: Initial-condition kinds this model adds: kind -> (required keys, defaults, description);
    #: built by :meth:`initial_cell_averages`.
    initial_kinds: ClassVar[dict[str, tuple[tuple[str, ...], dict[str, Any], str]]] = {}
    #: This model's meaning of a parameter where it differs from the one declared in its
    #: ``Parameters`` (a 2D model sharing the 1D model's parameters): key -> meaning
    #: (docs/parameters.md takes it from here).
    parameter_meanings: ClassVar[Mapping[str, str]] = {}
    #: What :meth:`is_admissible` requires, for error messages.
    admissible_rule: ClassVar[str] = "every variable finite"

    def __init__(self, **params: Any) -> None:
        fields = {f.name for f in dataclasses.fields(self.Parameters)}
        for key in params:
            if key not in fields:
                raise ConfigError(
                    f"parameters.{key}: "
                    + unknown_name_message(f"parameter of model '{self.name}'", key, fields)
                    if fields
                    else f"parameters.{key}: model '{self.name}' takes no parameters"
                )
        self.params = self.Parameters(**params)
        self._arrays: Any = None
        self._arrays_y: Any = None

    def __getstate__(self) -> dict[str, Any]:
        """The model without its compiled array kernels (a cache, rebuilt on first use), so
        that a model can be pickled, e.g. to draw a run's figures in another process."""
        state = self.__dict__.copy()
        state["_arrays"] = None
        state["_arrays_y"] = None
        return state

    # ------------------------------------------------------------------ parameters, coefficients
    @property
    def n_vars(self) -> int:
        """Number of conserved variables."""
        return len(self.variables)

    @property
    def n_aux(self) -> int:
        """Number of static per-point coefficients."""
        return len(self.aux_names)

    def check_domain(self, x_min: float, x_max: float) -> None:
        """Raise ConfigError if the model's own data (a terrain table, say) do not cover the
        domain ``[x_min, x_max]``. The default has nothing to check."""
        return None

    def check_domain_2d(self, grid: Grid2D) -> None:
        """Raise ConfigError if a 2D model's own data (a chute table, a terrain) do not cover
        the rectangle of ``grid``. The default checks the x range by :meth:`check_domain`.

        Parameters
        ----------
        grid : Grid2D
        """
        self.check_domain(grid.x.x_min, grid.x.x_max)

    def on_grid_2d(self, grid: Grid2D) -> Model:
        """The model as a scheme on ``grid`` runs it: the model itself (the default), or, for a
        model whose own data are finer than the grid's cells (a terrain from a DEM with smaller
        cells), a copy with those data at the grid's resolution.

        Parameters
        ----------
        grid : Grid2D

        Returns
        -------
        Model
        """
        return self

    def check_boundaries_2d(self, kinds: Mapping[str, str]) -> None:
        """Raise ConfigError if a 2D model's own data cannot take the side kinds ``kinds``
        (``left``, ``right``, ``bottom``, ``top`` -> kind name); the default accepts any.

        Parameters
        ----------
        kinds : mapping
        """
        return None

    def scene_dem(self, grid: Grid2D) -> Any:
        """A 2D model's terrain on the cells of ``grid`` as an elevation model with its
        georeference, for hazard maps (:mod:`conslaw.terrain.hazard_maps`); None without a terrain
        (the default).

        Parameters
        ----------
        grid : Grid2D

        Returns
        -------
        conslaw.terrain.dem.DigitalElevationModel or None
        """
        return None

    def param_vector(self) -> Array:
        """The parameters packed as float64, in the field order of :attr:`Parameters`."""
        values = [float(getattr(self.params, f.name)) for f in dataclasses.fields(self.Parameters)]
        return np.array(values if values else [0.0], dtype=np.float64)

    def aux(self, x: Array, dx: float) -> Array:
        """Static coefficients of the cells of width ``dx`` centred at ``x``, ``(n_aux, len(x))``.

        The scheme asks for whole cells (width dx) at cell centres and for half cells (width
        dx/2) at the quarter points, so coefficients may be exact cell averages.
        """
        return np.zeros((self.n_aux, np.asarray(x).shape[0]), dtype=np.float64)

    def aux_2d(self, x: Array, y: Array) -> Array:
        """Static coefficients at the map points ``(x, y)`` (broadcast), ``(n_aux, *shape)``,
        of a 2D model whose :attr:`aux_layout_2d` is ``"field"``.

        Parameters
        ----------
        x, y : numpy.ndarray

        Returns
        -------
        numpy.ndarray
        """
        shape = np.broadcast_shapes(np.shape(x), np.shape(y))
        return np.zeros((self.n_aux, *shape), dtype=np.float64)

    def flow_depth_and_speed(self, q: Array, aux: Array | None) -> tuple[Array, Array] | None:
        """The flow depth and speed of 2D cell values ``q`` ``(n_vars, ny, nx)`` for hazard maps
        (:mod:`conslaw.peak_fields`), or None for a model without a depth. The default: the
        depth row, and the length of the velocity (0 where the depth is below
        :meth:`dry_depth`).

        Parameters
        ----------
        q : numpy.ndarray
        aux : numpy.ndarray or None
            The coefficients at the same cells (``aux_2d``), for a model that needs them.

        Returns
        -------
        tuple of numpy.ndarray or None
        """
        d = self.depth_index
        if d is None:
            return None
        depth = np.asarray(q[d], dtype=np.float64)
        wet = (depth >= self.dry_depth()) & (depth > 0.0)
        safe = np.where(wet, depth, 1.0)
        rows = [m for m in (self.momentum_index, self.momentum_y_index) if m is not None]
        size = np.sqrt(sum(np.asarray(q[m], dtype=np.float64) ** 2 for m in rows))
        return depth, np.where(wet, size / safe, 0.0)

    def uniform_aux(self) -> bool:
        """Whether :meth:`aux` gives the same coefficients at every position and width, so that
        a scheme may ask once (front tracking at its moving margins). Default: only a model
        without coefficients; a model whose coefficients are uniform says so."""
        return self.n_aux == 0

    def initial_cell_averages(self, kind: str, options: Mapping[str, Any], grid: Grid) -> Array:
        """Exact cell averages of one of this model's :attr:`initial_kinds`."""
        raise NotImplementedError(f"model '{self.name}' has no initial condition '{kind}'")

    def initial_cell_averages_2d(
        self, kind: str, options: Mapping[str, Any], grid: Grid2D
    ) -> Array:
        """Cell averages ``(n_vars, ny, nx)`` of one of a 2D model's :attr:`initial_kinds`."""
        raise NotImplementedError(f"model '{self.name}' has no initial condition '{kind}'")

    def figures(self) -> dict[str, Callable[..., Any]]:
        """Figures of a run that only this model can draw: file name -> ``f(result)`` returning
        a matplotlib ``Figure`` (``conslaw run`` writes them with the others,
        :func:`conslaw.plotting.figures_for`). None by default."""
        return {}

    def kernel_variant(self) -> str:
        """In a few words, which of the model's compiled kernels these parameters need, where
        parameters choose between several (:meth:`capabilities`); "" if there is one. Said when
        a run compiles, so that a second compile for the same model is not a surprise."""
        return ""

    def capabilities(self) -> dict[str, bool]:
        """What this instance uses; the compiled kernels leave out everything else.

        Keys: ``source`` (source term), ``balanced_source`` (staggered-cell source),
        ``surface`` (surface reconstruction of the depth), ``correction`` (pointwise correction),
        ``resistance`` (Coulomb-type resistance), ``dynamic_coefficients`` (per-cell coefficients
        from the slopes), ``interface_coefficients`` (one coefficient per staggered cell for its
        two fluxes), ``rest_coefficients`` (a range of coefficients for material at rest). A
        model whose parameters switch a term off (a flat bed) overrides this.
        """
        return {
            "source": bool(self.has_source),
            "balanced_source": self.balanced_source_point is not None,
            "surface": self.surface_aux is not None,
            "correction": self.correct_point is not None,
            "resistance": self.resistance_point is not None,
            "dynamic_coefficients": self.coefficients_point is not None
            or self.coefficients_2d_point is not None,
            "interface_coefficients": self.interface_coefficients_point is not None
            or self.corner_coefficients_point is not None,
            "rest_coefficients": self.rest_coefficients_point is not None,
        }

    def conserved_rows(self) -> tuple[int, ...]:
        """Variables whose total only changes through the boundaries (no source, no
        resistance): the ones a mass-drift report may check."""
        uses = self.capabilities()
        if not (uses["source"] or uses["balanced_source"] or uses["resistance"]):
            return tuple(range(self.n_vars))
        return () if self.depth_index is None else (self.depth_index,)

    def dry_depth(self) -> float:
        """Depth below which a cell counts as dry (velocity 0); 0 for models without depth."""
        return 0.0

    def primitive_fields(self, q: Array) -> dict[str, Array]:
        """Primitive variables of every column of ``q`` by name, for output files and plots.

        Default: the conserved variables themselves. A depth-averaged model returns the depth
        and the velocity (see :class:`conslaw_models.depth_averaged.DepthAveragedModel`).
        """
        return {name: np.asarray(q[v]) for v, name in enumerate(self.variables)}

    def coefficient_fields(self, x: Array, coefficients: Array) -> dict[str, Array]:
        """Named per-cell coefficients for output files, from the cell centres ``x`` and the
        coefficients the scheme uses there (``(n_aux, n)``, see
        :meth:`conslaw.schemes.base.Scheme.cell_coefficients`). Default: the rows of
        :meth:`aux` by :attr:`aux_names`."""
        return {name: np.asarray(coefficients[i]) for i, name in enumerate(self.aux_names)}

    def parameter_dict(self) -> dict[str, Any]:
        """The parameters as a plain dictionary (for the resolved scene file)."""
        return dataclasses.asdict(self.params)

    # ------------------------------------------------------------------ compiled kernels
    #: The hooks a kernel template binds, by placeholder name (``_<hook>``).
    KERNEL_HOOKS: ClassVar[tuple[str, ...]] = (
        "flux_point", "jacobian_point", "max_speed_point", "source_point", "admissible_point",
        "balanced_source_point", "correct_point", "resistance_point", "coefficients_point",
        "interface_coefficients_point", "rest_coefficients_point",
    )  # fmt: skip

    def kernel_bindings(self) -> dict[str, Callable[..., Any]]:
        """The model's pointwise functions under the placeholder names of the kernel templates
        (``_flux_point``, ...). A hook the model does not have is bound to a stand-in of
        :mod:`conslaw.pointwise` that the matching constant of :meth:`kernel_constants` leaves
        uncalled; without its own admissibility, a model's states are admissible when finite."""
        model_class = type(self)
        bindings: dict[str, Callable[..., Any]] = {}
        for hook in self.KERNEL_HOOKS:
            default = pointwise.finite_point if hook == "admissible_point" else pointwise.unbound
            bindings[f"_{hook}"] = getattr(model_class, hook, None) or default
        return bindings

    def kernel_constants(self) -> dict[str, bool | int | float]:
        """The compile-time constants of the model in a kernel: sizes, which hooks it uses
        (``HAS_*``, dead branches are removed) and the rows and depth of a depth-averaged model."""
        uses = self.capabilities()
        bed, bed_slope = self.surface_aux if uses["surface"] and self.surface_aux else (-1, -1)
        depth = self.depth_index
        return {
            "NV": int(self.n_vars),
            "NAUX": int(self.n_aux),
            "NPARAMS": len(self.param_vector()),
            "HAS_SOURCE": uses["source"],
            "HAS_BALANCED_SOURCE": uses["balanced_source"],
            "HAS_CORRECTION": uses["correction"],
            "HAS_RESISTANCE": uses["resistance"],
            "HAS_DYNAMIC_COEFFICIENTS": uses["dynamic_coefficients"],
            "HAS_INTERFACE_COEFFICIENTS": uses["interface_coefficients"],
            "HAS_REST_COEFFICIENTS": uses["rest_coefficients"],
            "DEPTH": -1 if depth is None else int(depth),
            "MOMENTUM": -1 if self.momentum_index is None else int(self.momentum_index),
            "DRY_DEPTH": float(self.dry_depth()),
            "SURFACE_BED": int(bed),
            "SURFACE_SLOPE": int(bed_slope),
        }

    # ------------------------------------------------------------------ derived array methods
    def _compiled_arrays(self) -> Any:
        """Compiled loops over the cells of the pointwise functions (``array_kernels_template``)."""
        if self._arrays is None:
            constants = self.kernel_constants()
            keys = (
                "NV", "NAUX", "HAS_SOURCE", "HAS_BALANCED_SOURCE", "HAS_CORRECTION",
                "HAS_RESISTANCE", "HAS_DYNAMIC_COEFFICIENTS", "HAS_INTERFACE_COEFFICIENTS",
                "HAS_REST_COEFFICIENTS",
            )  # fmt: skip
            self._arrays = generate(
                Path(__file__).with_name("array_kernels_template.py"),
                self.kernel_bindings(),
                {key: constants[key] for key in keys},
            )
        return self._arrays

    @property
    def n_dims(self) -> int:
        """Space dimensions of the model's equations: 2 if it has a y flux, else 1."""
        return 1 if type(self).flux_y_point is None else 2

    def _compiled_arrays_y(self) -> Any:
        """The loops of :meth:`_compiled_arrays` with the y-direction functions bound in place
        of the x ones (the same template: ``flux_cells`` then evaluates ``g``)."""
        if self.n_dims != 2:
            raise TypeError(f"model '{self.name}' is one-dimensional: it has no y flux")
        if self._arrays_y is None:
            model_class = type(self)
            bindings = {
                **self.kernel_bindings(),
                "_flux_point": model_class.flux_y_point,
                "_jacobian_point": model_class.jacobian_y_point,
                "_max_speed_point": model_class.max_speed_y_point,
                "_balanced_source_point": model_class.balanced_source_y_point or pointwise.unbound,
            }
            constants = self.kernel_constants()
            keys = ("NV", "NAUX", "HAS_SOURCE", "HAS_BALANCED_SOURCE")
            self._arrays_y = generate(
                Path(__file__).with_name("array_kernels_template.py"),
                bindings,  # type: ignore[arg-type]
                {key: constants[key] for key in keys},
            )
        return self._arrays_y

    def _arrays_along(self, direction: str) -> Any:
        """The compiled loops of the x (:meth:`_compiled_arrays`) or y direction."""
        if direction == "x":
            return self._compiled_arrays()
        if direction == "y":
            return self._compiled_arrays_y()
        raise ValueError(f"direction must be 'x' or 'y', got {direction!r}")

    def _prepare(self, q: Array, aux: Array | None) -> tuple[Array, Array]:
        q = np.ascontiguousarray(q, dtype=np.float64)
        if q.ndim == 1 and self.n_vars == 1:
            q = q[None, :]
        if q.ndim != 2 or q.shape[0] != self.n_vars:
            raise ValueError(f"q must have shape ({self.n_vars}, n), got {q.shape}")
        if aux is None:
            aux = np.zeros((self.n_aux, q.shape[1]), dtype=np.float64)
        return q, np.ascontiguousarray(aux, dtype=np.float64)

    def flux(self, q: Array, aux: Array | None = None, direction: str = "x") -> Array:
        """Physical flux of every column of ``q``, shape ``(n_vars, n)``: ``f(q)``, or the y
        flux ``g(q)`` of a 2D model with ``direction="y"``."""
        q, aux = self._prepare(q, aux)
        out = np.empty_like(q)
        self._arrays_along(direction).flux_cells(q, aux, self.param_vector(), out)
        return out

    def flux_jacobian(self, q: Array, aux: Array | None = None, direction: str = "x") -> Array:
        """Flux Jacobian ``A = df/dq`` (or ``B = dg/dq``, ``direction="y"``) of every column,
        shape ``(n_vars, n_vars, n)``."""
        q, aux = self._prepare(q, aux)
        out = np.empty((self.n_vars, self.n_vars, q.shape[1]), dtype=np.float64)
        self._arrays_along(direction).jacobian_cells(q, aux, self.param_vector(), out)
        return out

    def max_wave_speed(self, q: Array, aux: Array | None = None, direction: str = "x") -> Array:
        """Largest absolute eigenvalue of the flux Jacobian of ``direction`` in every column,
        shape ``(n,)``."""
        q, aux = self._prepare(q, aux)
        out = np.empty(q.shape[1], dtype=np.float64)
        self._arrays_along(direction).max_speed_cells(q, aux, self.param_vector(), out)
        return out

    def source(self, q: Array, aux: Array | None = None) -> Array:
        """Source term ``s(q)`` of every column (zeros for a model without source)."""
        q, aux = self._prepare(q, aux)
        out = np.zeros_like(q)
        if self.capabilities()["source"]:
            self._compiled_arrays().source_cells(q, aux, self.param_vector(), out)
        return out

    def balanced_source(
        self, predicted: Array, aux: Array, dx: float, direction: str = "x"
    ) -> Array:
        """``balanced_source_point`` between neighbouring columns, shape ``(n_vars, n-1)``
        (``balanced_source_y_point`` with ``direction="y"``, ``dx`` then the spacing in y)."""
        q, aux = self._prepare(predicted, aux)
        out = np.zeros((self.n_vars, q.shape[1] - 1))
        arrays = self._arrays_along(direction)
        arrays.balanced_source_cells(q, aux, dx, self.param_vector(), out)
        return out

    def correct(self, q: Array, aux: Array, dt: float) -> Array:
        """``correct_point`` applied to a copy of every column of ``q``."""
        q, aux = self._prepare(q, aux)
        out = q.copy()
        self._compiled_arrays().correct_cells(out, aux, self.param_vector(), dt)
        return out

    def resistance(self, q: Array, aux: Array | None = None) -> Array:
        """``resistance_point`` of every column (zeros without resistance), shape ``(n,)``."""
        q, aux = self._prepare(q, aux)
        out = np.zeros(q.shape[1])
        if self.capabilities()["resistance"]:
            self._compiled_arrays().resistance_cells(q, aux, self.param_vector(), out)
        return out

    def dynamic_coefficients(self, q: Array, slopes: Array, aux: Array) -> Array:
        """Copy of ``aux`` with ``coefficients_point`` applied column by column."""
        q, aux = self._prepare(q, aux)
        out = aux.copy()
        if self.capabilities()["dynamic_coefficients"]:
            slopes = np.ascontiguousarray(slopes, dtype=np.float64)
            self._compiled_arrays().coefficients_cells(q, slopes, out, self.param_vector())
        return out

    def interface_coefficients(
        self, left: Array, right: Array, aux_left: Array, aux_right: Array
    ) -> tuple[Array, Array]:
        """Copies of ``aux_left``, ``aux_right`` with ``interface_coefficients_point`` applied to
        every pair of columns (the two ends of one staggered cell)."""
        left, aux_left = self._prepare(left, aux_left)
        right, aux_right = self._prepare(right, aux_right)
        out_left, out_right = aux_left.copy(), aux_right.copy()
        if self.capabilities()["interface_coefficients"]:
            self._compiled_arrays().interface_coefficients_cells(
                left, right, out_left, out_right, self.param_vector()
            )
        return out_left, out_right

    def coefficients_2d(self, q: Array, slopes_x: Array, slopes_y: Array, aux: Array) -> Array:
        """Copy of ``aux`` with ``coefficients_2d_point`` applied column by column (``aux``
        itself, copied, if the model does not use it).

        Parameters
        ----------
        q, slopes_x, slopes_y : numpy.ndarray
            ``(n_vars, n)``: the cells' values and their limited slopes in x and in y.
        aux : numpy.ndarray
            ``(n_aux, n)``: the cells' static coefficients.

        Returns
        -------
        numpy.ndarray
            ``(n_aux, n)``.
        """
        q, out = self._prepare(q, aux)
        out = out.copy()
        point = type(self).coefficients_2d_point
        if point is not None and self.capabilities()["dynamic_coefficients"]:
            coefficients_2d_cells(
                point,
                q,
                np.ascontiguousarray(slopes_x, dtype=np.float64),
                np.ascontiguousarray(slopes_y, dtype=np.float64),
                out,
                self.param_vector(),
            )
        return out

    def corner_coefficients(self, a: Array, b: Array, c: Array, d: Array, aux: Array) -> Array:
        """Copy of ``aux`` with ``corner_coefficients_point`` applied to every column of the
        corner states.

        Parameters
        ----------
        a, b, c, d : numpy.ndarray
            ``(n_vars, n)``: the lower-left, lower-right, upper-left and upper-right corner
            states of ``n`` staggered cells.
        aux : numpy.ndarray
            ``(n_aux, n)``: their static coefficients.

        Returns
        -------
        numpy.ndarray
            ``(n_aux, n)``.
        """
        a, b, c, d = (self._prepare(q, None)[0] for q in (a, b, c, d))
        out = np.array(aux, dtype=np.float64, order="C", copy=True)
        point = type(self).corner_coefficients_point
        if point is not None and self.capabilities()["interface_coefficients"]:
            corner_coefficients_cells(point, a, b, c, d, out, self.param_vector())
        return out

    def rest_coefficients(self, aux: Array) -> tuple[Array, Array]:
        """The low and high ends of the range of coefficients of material whose coefficients
        are not determined (``rest_coefficients_point`` applied to two copies of ``aux``)."""
        low = np.array(aux, dtype=np.float64, order="C", copy=True)
        high = low.copy()
        if self.capabilities()["rest_coefficients"]:
            self._compiled_arrays().rest_coefficients_cells(low, high, self.param_vector())
        return low, high

    def is_admissible(self, q: Array, aux: Array | None = None) -> NDArray[np.bool_]:
        """Whether every column of ``q`` lies in the admissible set (finite, and model rules)."""
        q, aux = self._prepare(q, aux)
        out = np.empty(q.shape[1], dtype=np.bool_)
        self._compiled_arrays().admissible_cells(q, aux, self.param_vector(), out)
        return out

    # ------------------------------------------------------------------ exact solutions
    def exact_solution(
        self, initial: InitialData, grid: Grid, context: Mapping[str, Any]
    ) -> ExactSolution | None:
        """The exact solution for this set-up, or None if the model has none.

        ``context`` holds ``left`` and ``right`` (boundary names) and ``t_end`` (the last output
        time). Raise :class:`conslaw.exact.Unavailable` with the reason when the model has exact
        solutions but none applies here (waves reach a boundary before ``t_end``, ...).
        """
        return None

    def exact_solution_2d(
        self, initial: InitialData, grid: Grid2D, context: Mapping[str, Any]
    ) -> ExactSolution2D | None:
        """A 2D model's exact solution for this set-up, or None if it has none.

        ``context`` holds the four sides' boundary names (``left``, ``right``, ``bottom``,
        ``top``) and ``t_end``; raise :class:`conslaw.exact.Unavailable` with the reason when
        the model has exact solutions but none applies here.
        """
        return None
