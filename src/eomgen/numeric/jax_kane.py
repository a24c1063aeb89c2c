"""Kane's equations in JAX: the pieces of `kane_catalogue` as JAX functions (`jax_functions.JaxPrinted`)
and the algorithms of `numeric.kane` run with jax.numpy as their array module, so that `jax.jit`,
`jax.vmap` and `jax.grad` / `jax.jacfwd` go through mass_matrix, forcing, the speeds, rhs and energy.
Inside `jax.jit` (or vmap) no value is checked: a rolling disk lying flat is refused only on concrete
states; shapes are checked."""
from __future__ import annotations

import jax
import jax.numpy as jnp

from .jax_functions import JaxPrinted
from .kane import NumericKane


class JaxKane(JaxPrinted, NumericKane):
    """`NumericKane` whose pieces are JAX functions and whose algorithms run in jax.numpy."""

    xp = jnp

    def _check_flat(self, q, params) -> None:
        if not isinstance(q, jax.core.Tracer):  # a traced value cannot raise
            super()._check_flat(q, params)
