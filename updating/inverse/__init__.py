"""The inverse problem: the modified error and its weights, the thresholds, the localisation-
correction loop, the confidence intervals and the plan of a test."""
