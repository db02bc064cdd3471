"""What the figure tests read off a drawn matplotlib figure (shared by the analysis tests)."""


def x_extent(patch) -> tuple[float, float]:
    """(x0, x1) in data units of an axvspan (a Rectangle in data x, or an older matplotlib's Polygon)."""
    v = patch.get_patch_transform().transform(patch.get_path().vertices)
    return float(v[:, 0].min()), float(v[:, 0].max())
