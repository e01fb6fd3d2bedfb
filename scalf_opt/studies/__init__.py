"""Studies built on the pipeline: the paper's reproduction (Tables 5 and 6) and, later, sweeps."""
