"""Joint updating: residuals, localisation-correction strategy, reports and the command line."""

__all__: list[str] = []
