"""The robot as Pinocchio sees it: the whole tree, its sagittal legs, their CasADi twin, kinematics.

Nothing here knows about gaits, actuators or energy; everything above reads the robot from here.
"""
