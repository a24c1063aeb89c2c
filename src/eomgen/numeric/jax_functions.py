"""The JAX backend: the catalogue's functions as JAX functions of one state (`printers.traced`), N states
by `jax.vmap`, and the numeric algorithms in jax.numpy, so that `jax.jit`, `jax.vmap` and
`jax.grad` / `jax.jacfwd` go through them:

    forward_dynamics:  u̇ = M⁻¹ h,  h = τ + Sᵀ τ_a − b − g
    forward_dynamics_derivatives:  (−M⁻¹ D_q, −M⁻¹ D_u, M⁻¹),  D = ∂(τ_ID − τ_loads)/∂(q, u) at u̇ = M⁻¹ h
    constrained_dynamics:  F_c = −(J M⁻¹ Jᵀ)⁻¹ (J M⁻¹ h + c),  u̇ = M⁻¹ (h + Jᵀ F_c)
    rhs:  ẋ = [q̇(q, u), u̇]

float64 by default (JAX's 64-bit mode, `jax_enable_x64`, is switched on when such functions are made);
float32 with dtype="float32". On CPU the values come from the C backend's compiled kernels by default
(kernels="c", `jax_kernels`: one C call per vmapped batch, derivatives from the traced graph);
kernels="xla" traces the printed graph everywhere. Inside `jax.jit` no value is checked by the graph
(NaN, infinities: JAX cannot raise on values; the C kernels raise); shapes are. J in the constrained
dynamics holds the rows some motion can violate at three random states (`constrained.row_sizes`), fixed
when the functions are made."""
from __future__ import annotations

import numpy as np

from ..errors import ModelError
from ..printers.traced import TRACED, jax_function, refuse_branches
from ..printers.walker import Generated, writer
from .constrained import closure_index, row_sizes
from .equations import NumericEoM
from .jax_kernels import Kernels, kernel_function, kernels_for

DTYPES = ("float64", "float32")
FUSION_LIMIT = 1000  # operations: larger functions are compiled without XLA's fusion pass (`_jitted`)
NO_FUSION = {"xla_disable_hlo_passes": "fusion"}


class JaxPrinted:
    """Mixed into a facade: its catalogue's functions printed as JAX functions (one state or N along axis
    0; params by name, or bound); `jax[key]` is the function of one state (q, u, ud, p) → array, p the
    parameter vector. kernels (`jax_kernels.kernels_for`): "c", its values on CPU from the C backend's
    kernels, "xla" the traced graph everywhere."""

    def __init__(self, equations, dtype: str = "float64", kernels: str | None = None) -> None:
        import jax

        if dtype not in DTYPES:
            raise ModelError(f"dtype: expected one of {list(DTYPES)}, got {dtype!r}")
        self.kernels, self._asked = kernels_for(kernels), kernels
        if dtype == "float64":
            jax.config.update("jax_enable_x64", True)
        self.dtype = dtype
        super().__init__(equations)

    def _print(self, keys: list[str]) -> None:
        traced = writer(self.catalogue, TRACED)
        c = vars(self).setdefault("_c", Kernels(self.catalogue, required=self._asked == "c"))  # compiles
        # nothing until a call on CPU
        for key in keys:
            fn = self.catalogue.printable(key)
            expr = fn.expression()
            refuse_branches(self.catalogue.sub, expr, key, "the JAX backend")
            source, shape, ops = traced.source("f", expr, fn.symmetric)
            function = jax_function(source, shape, key)
            if self.kernels == "c":
                function = kernel_function(function, key, shape, c)
            self.functions[key] = Generated(source, shape, ops, function)

    @property
    def jax(self):
        """The JAX function of one state of each catalogue function, by key: f.jax["M"](q, u, ud, p)."""
        return _ByKey(self)

    def _state(self, q, u, ud):
        import jax.numpy as jnp

        q = jnp.asarray(q, self.dtype)
        if q.ndim not in (1, 2) or q.shape[-1] != self.nq:
            raise ModelError(f"q: expected shape ({self.nq},) or (N, {self.nq}), got {q.shape}")
        shape = q.shape[:-1] + (self._nu,)
        given = [jnp.zeros(shape, self.dtype) if x is None else jnp.asarray(x, self.dtype) for x in (u, ud)]
        for name, x in zip(("u", "ud"), given):
            if x.shape != shape:
                raise ModelError(f"{name}: expected shape {shape}, got {x.shape}")
        return q, *given

    def call(self, key, q, u=None, ud=None, params=None, out=None):
        import jax
        import jax.numpy as jnp

        if out is not None:
            raise ModelError("out: the JAX backend returns new arrays (JAX arrays cannot be written into)")
        q, u, ud = self._state(q, u, ud)
        p = jnp.asarray(self.parameter_vector(params, key), self.dtype)
        if q.ndim == 1:  # one state: as traced by the caller's jit (or op by op)
            return self.generated(key).function(q, u, ud, p)
        traced = any(isinstance(x, jax.core.Tracer) for x in (q, u, ud, p))  # inside the caller's jit
        return self._batch(key, traced)(q, u, ud, p)

    def _batch(self, key: str, traced: bool):
        """`key`'s function vmapped over a batch, jitted once unless the caller's jit traces it: without
        XLA's fusion pass for a function of more than `FUSION_LIMIT` operations, which copies each shared
        intermediate into every fusion that reads it (talos's M: 47 s to compile with it, 10 s without;
        benchmarks/targets.py). Op by op, a batch of 1000 ur5 states took 80 ms; jitted, 1 ms."""
        import jax

        f = self.generated(key)
        body = jax.vmap(f.function, in_axes=(0, 0, 0, None))
        if traced:
            return body
        cache = vars(self).setdefault("_jit", {})
        if key not in cache:
            cache[key] = jax.jit(body, compiler_options=NO_FUSION if f.ops > FUSION_LIMIT else None)
        return cache[key]

    def _actuated(self, h, tau_a):
        """h + Sᵀ τ_a (τ_a: one value per actuated joint; shapes checked, values not: JAX cannot raise on
        them)."""
        import jax.numpy as jnp

        if tau_a is None:
            return h
        tau_a = jnp.asarray(tau_a, self.dtype)
        if tau_a.shape[-1:] != (self.S.shape[0],):
            raise ModelError(f"tau_a: expected {self.S.shape[0]} values (one per actuated joint), got shape "
                             f"{tau_a.shape}")
        return h + tau_a @ jnp.asarray(self.S, self.dtype)


class JaxEoM(JaxPrinted, NumericEoM):
    """`NumericEoM` whose functions are JAX functions (`JaxPrinted`), its algorithms in jax.numpy."""

    def _h(self, q, u, tau_a, params):
        return self._actuated(self.tau(q, u, params) - self.nle(q, u, params), tau_a)

    def forward_dynamics(self, q, u, tau_a=None, params=None):
        import jax.numpy as jnp

        return jnp.linalg.solve(self.M(q, params), self._h(q, u, tau_a, params)[..., None])[..., 0]

    def forward_dynamics_derivatives(self, q, u, tau=None, params=None):
        import jax.numpy as jnp

        self.catalogue["FD_derivatives"]  # refused with the reason where there are none
        h = self._h(q, u, None, params) + (0.0 if tau is None else jnp.asarray(tau, self.dtype))
        M_inv = jnp.linalg.inv(self.M(q, params))
        ud = jnp.einsum("...ij,...j->...i", M_inv, h)
        D = -M_inv @ self.call(self.catalogue["FD_derivatives"].parts[1], q, u, ud, params)
        return D[..., :self.nv], D[..., self.nv:], M_inv

    def constrained_dynamics(self, q, u, tau_a=None, params=None, baumgarte=None):
        """(u̇, F_c) with every constraint row some motion can violate held (module formulas), F_c stacked
        like J_c's rows (0 on the others); one state or N."""
        import jax
        import jax.numpy as jnp

        with jax.ensure_compile_time_eval():  # at three random states, also inside jax.jit
            rows = np.flatnonzero(row_sizes(self, params) > 0)
        M, h = self.M(q, params), self._h(q, u, tau_a, params)
        J, c = self.contact_jacobian(q, params), self.contact_jacobian_dot_u(q, u, params)
        if baumgarte is not None:
            alpha, beta = baumgarte
            c = c + 2 * alpha * jnp.einsum("...ij,...j->...i", J, u)
            if self.closure_rows:
                c = c.at[..., closure_index(self.system)].add(beta ** 2 * self.closure_residual(q, params))
        J, c = J[..., rows, :], c[..., rows]
        M_inv_Jt = jnp.linalg.solve(M, jnp.swapaxes(J, -1, -2))
        M_inv_h = jnp.linalg.solve(M, h[..., None])[..., 0]
        F = -jnp.linalg.solve(J @ M_inv_Jt, jnp.einsum("...ij,...j->...i", J, M_inv_h) + c)
        ud = M_inv_h + jnp.einsum("...ij,...j->...i", M_inv_Jt, F)
        return ud, jnp.zeros(h.shape[:-1] + (len(self.constraint_rows),), h.dtype).at[..., rows].set(F)

    def rhs(self, t, x, tau=None, params=None, baumgarte=None):
        """ẋ = [q̇(q, u), u̇]: u̇ of `forward_dynamics`, or of `constrained_dynamics` with contacts, loops or
        rolling disks; τ_a = `tau` (None, values or a function (t, q, u)); no DC motors."""
        import jax.numpy as jnp

        if self.system.motors:
            raise ModelError(f"the JAX backend's rhs does not integrate the DC motors "
                             f"{[str(m.current) for m in self.system.motors]}: use the NumPy or C backend")
        if self.system.prescribed:
            raise ModelError(f"the JAX backend's rhs does not give the time to the prescribed motion of "
                             f"joint '{self.system.prescribed[0].name}': use the NumPy or C backend")
        x = jnp.asarray(x, self.dtype)
        q, u = x[..., :self.nq], x[..., self.nq:]
        tau_a = tau(t, q, u) if callable(tau) else tau
        if self.constraint_rows:
            ud = self.constrained_dynamics(q, u, tau_a, params, baumgarte)[0]
        else:
            ud = self.forward_dynamics(q, u, tau_a, params)
        return jnp.concatenate([self.qdot(q, u, params), ud], axis=-1)


class _ByKey:
    """functions.jax[key]: the JAX function of catalogue function `key`."""

    def __init__(self, functions: JaxPrinted) -> None:
        self.functions = functions

    def __getitem__(self, key: str):
        return self.functions.generated(key).function
