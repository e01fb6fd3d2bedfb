"""Swing optimizers: the paper's pattern search and a CasADi/Ipopt NLP, on one problem type."""
