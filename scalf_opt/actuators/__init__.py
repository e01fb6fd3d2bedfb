"""Joint drives: what a joint's actuator adds to the rigid-body torques and powers.

Every drive implements :class:`~scalf_opt.actuators.drive.Drive` (its per-sample outputs, the
power it draws beyond the joint's mechanical power, and bounds on its outputs). The energy
pipeline works through that interface only; new drives plug in here, one module each.
"""
