"""Data in and out: measured and simulated fields (CSV, UFF 58), probes, run files and atomic
writes."""
