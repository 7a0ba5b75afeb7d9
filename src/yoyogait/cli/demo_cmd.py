"""``yoyogait demo``: the estimator on a synthetic walk (placeholder until the full demo)."""
