"""Physics check of the energy model: a MuJoCo simulation of the planned trot.

The MuJoCo model is built from the robot's URDF (:mod:`~scalf_opt.sim.mujoco_model`): the
trunk moves in the sagittal plane only (slide x, slide z, hinge pitch: the paper's assumption
(a)), every joint but the legs' hip pitch and knee is fixed, round feet touch a flat ground with
friction; the settings are derived from the robot (:mod:`~scalf_opt.sim.settings`). The legs
follow the plan (:mod:`~scalf_opt.sim.plan`) with the energy pipeline's inverse-dynamics torques
as feed-forward plus feedback, on each swing joint and on the trunk in stance
(:mod:`~scalf_opt.sim.control`); :mod:`~scalf_opt.sim.run` steps the simulation and records it,
:mod:`~scalf_opt.sim.metrics` measures what the constant-height model assumes (trunk height,
pitch, speed, foot slip, foot forces), the servo's own work and the joint energy beside the
model's prediction, and :mod:`~scalf_opt.sim.inverse` what the plan costs when followed exactly
(MuJoCo's inverse dynamics of the whole robot on it).

Only this package imports ``mujoco`` (the optional ``sim`` extra).
"""
