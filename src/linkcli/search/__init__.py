"""The optimization toolkit every problem type shares: budget, sampling, polish."""
