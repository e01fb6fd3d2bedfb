"""Swing-foot trajectory families: the cubic-spline reference and truncated Fourier series.

Every family meets the swing's end conditions (position and velocity at lift-off and touch-down
equal the stance path's) by construction; the mid-swing clearance, the foot at least H above the
ground at s = 1/2 (decision 14), is a constraint of the optimization problem, which the reference
spline meets with equality (its apex knot).

* :mod:`~scalf_opt.locomotion.swing.boundary`: the end conditions in foot and joint space;
* :mod:`~scalf_opt.locomotion.swing.family`: the family interface and the affine path;
* :mod:`~scalf_opt.locomotion.swing.reference`: the clamped cubic splines (decision 12);
* :mod:`~scalf_opt.locomotion.swing.fourier`: the Fourier families (decision 13);
* :mod:`~scalf_opt.locomotion.swing.names`: family names (cheap to import);
* :mod:`~scalf_opt.locomotion.swing.registry`: families by name.
"""
