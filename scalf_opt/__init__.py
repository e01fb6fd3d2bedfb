"""scalf-opt: energy-efficient swing-foot trajectories for legged robots.

The package implements, and extends, the energy model and swing-trajectory optimization of the
hydraulic quadruped SCalf (Energies 2019, 12(13), 2514): Pinocchio for rigid-body kinematics and
dynamics, a CasADi twin of the leg for symbolic derivatives, a hydraulic-cylinder energy model with
Stribeck friction, and two optimizers (the paper's pattern search and an Ipopt NLP).
"""

__version__ = "0.1.0"
