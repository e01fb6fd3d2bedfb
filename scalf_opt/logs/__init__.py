"""Energy from the robot's own measurements: the cylinder-log pipeline (the paper's Section 6.2).

A cylinder log (:mod:`~scalf_opt.logs.log_file`) holds, per leg and sample, the two cylinders'
lengths and forces. :mod:`~scalf_opt.logs.analysis` turns lengths into joint angles by the inverse
cylinder mapping (Eq. 67) and forces into torques by the moment arms (Eq. 68), differentiates the
lengths (:mod:`~scalf_opt.logs.derivative`) and sums the mechanical energy ``|F v|`` per leg and
phase over complete gait cycles (the paper's Table 7). :mod:`~scalf_opt.logs.sensors` writes such
a log from joint angles and torques, with the robot's sensor rate and accuracy.
"""
