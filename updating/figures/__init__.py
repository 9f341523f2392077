"""Figures (the optional matplotlib extra, loaded on use): cost curves, field maps, the residual
map, sweeps and plans."""
