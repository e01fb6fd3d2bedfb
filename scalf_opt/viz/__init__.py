"""What users read and look at: text reports and matplotlib figures (PNG, atomic, deterministic).

Matplotlib is imported only by :mod:`scalf_opt.viz.figures`, never by the layers below.
"""
