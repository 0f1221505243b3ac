"""Problem types, one package each (quick_return: design by time ratio)."""
