"""Energy of a trotting robot.

Per-sample leg physics over any drive, phases, cycles, and the compiled evaluator that computes a
whole cycle in one call.
"""
