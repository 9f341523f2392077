"""The model's response over a band: frequency sweeps and their power flow."""
