"""A per-point function mapped over many points, with its derivatives in blocks.

Both NLPs (the swing's, :mod:`~scalf_opt.optimize.nlp`, and the 3-D cycle's,
:mod:`~scalf_opt.optimize.whole_body_nlp`) evaluate one compiled function at many points whose
inputs do not share entries. Its Jacobian over all points is then the block diagonal of the
points' own, and a Hessian assembled from per-point blocks is too; CasADi's generic derivatives
through the mapped call propagate seeds colour by colour and cost several times more.
"""

from __future__ import annotations

import casadi as ca


def block_diagonal(blocks: ca.MX, pattern: ca.Sparsity, count: int) -> ca.MX:
    """``count`` blocks side by side (a mapped call's output, each ``pattern``) as one diagonal."""
    return ca.MX(ca.diagcat(*([pattern] * count)), blocks.nz[:])


def mapped_with_block_jacobian(fn: ca.Function, count: int, name: str) -> ca.Function:
    """``fn`` (one input column, one output column) at ``count`` points: ``vec(z) -> vec(out)``.

    ``z`` stacks the points' inputs column by column (``fn``'s input size times ``count``); the
    returned function's Jacobian is the block diagonal of ``fn``'s (a compiled ``fn`` brings its
    own compiled Jacobian), given to CasADi as a custom Jacobian.
    """
    n_in, n_out = fn.size1_in(0), fn.size1_out(0)
    jacobian = fn.jacobian()  # (z, out) -> d out / d z
    z_in, out_in = ca.MX.sym("z", n_in * count), ca.MX.sym("out", n_out * count)
    blocks = jacobian.map(count, "serial")(
        ca.reshape(z_in, n_in, count), ca.reshape(out_in, n_out, count)
    )
    custom = ca.Function(
        f"jac_{name}",
        [z_in, out_in],
        [block_diagonal(blocks, jacobian.sparsity_out(0), count)],
        ["i0", "out_o0"],
        ["jac_o0_i0"],
    )
    return ca.Function(
        name,
        [z_in],
        [ca.vec(fn.map(count, "serial")(ca.reshape(z_in, n_in, count)))],
        ["i0"],
        ["o0"],
        {"custom_jacobian": custom, "jac_penalty": 0},
    )
