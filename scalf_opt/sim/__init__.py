"""Physics check of the energy model: a MuJoCo simulation of the planned trot.

The MuJoCo model is built from the robot's URDF (:mod:`~scalf_opt.sim.mujoco_model`): the
trunk moves in the sagittal plane only (slide x, slide z, hinge pitch: the paper's assumption
(a)), every joint but the legs' hip pitch and knee is fixed, round feet touch a flat ground with
friction. The legs track the planned joint trajectories (:mod:`~scalf_opt.sim.plan`) with the
energy pipeline's inverse-dynamics torques as feed-forward plus joint PD
(:mod:`~scalf_opt.sim.control`); :mod:`~scalf_opt.sim.run` steps the simulation and records it,
:mod:`~scalf_opt.sim.metrics` measures what the constant-height model assumes (trunk height,
pitch, speed, foot slip, foot forces) and the joint energy beside the model's prediction.

Only this package imports ``mujoco`` (the optional ``sim`` extra).
"""
