"""L4: the browser designer (``assur design``) and its notebook widget :class:`Designer` (loaded on first use:
it needs the optional ``anywidget``)."""


def __getattr__(name):
    if name == "Designer":
        from .widget import Designer
        return Designer
    raise AttributeError(f"module 'assur.designer' has no attribute {name!r}")
