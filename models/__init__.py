"""Models that speak the engine's interface: benchmark problems with exact answers (and, later, the shell)."""
