"""SCalf, the paper's hydraulic quadruped: its URDF generator (``description``)."""
