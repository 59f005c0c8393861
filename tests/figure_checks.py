"""What the README's figure tests share: a stated figure against the value it must be, and the
hand-changed figure that --shift makes (docs_figures_test.py, docs_quoted_figures_test.py)."""


def report(checks, shift):
    """checks: (what, the README's figure as written, the value it must be, the distance allowed,
    a note printed after the value). shift: None, or (what, delta) to change that figure as if by
    hand. Prints every check; returns the exit status: with a shift, 0 when that figure and only
    it fails, otherwise 0 when none fails."""
    failed = []
    for what, figure, measured, allowed, note in checks:
        value = float(figure) + (shift[1] if shift and shift[0] == what else 0.0)
        ok = abs(value - measured) <= allowed
        if not ok:
            failed.append(what)
        shown = figure if value == float(figure) else f"{value:g} (changed)"
        print(f"{'ok    ' if ok else 'FAILED'} {what}: README {shown}, {note}")
    if shift:
        caught = failed == [shift[0]]
        print(f"the figure changed by hand {'fails, and only it' if caught else 'is not caught alone'}")
        return 0 if caught else 1
    return 1 if failed else 0
