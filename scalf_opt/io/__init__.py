"""Result files: ``summary.json``, ``samples.csv`` and CSV tables, written atomically."""
