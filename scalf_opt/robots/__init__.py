"""The robots scalf-opt knows.

Where their URDFs and actuator sidecars live, how their legs are named, and their nominal stance
height. SCalf's files ship with the package; HyQ's and Solo12's come from example-robot-data.
"""
