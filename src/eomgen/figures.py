"""Figures and animations that a Jupyter kernel shows by themselves: eg.plot's figure as a PNG and
eg.animate's animation as an HTML player, with no `%matplotlib inline` and no pyplot (IPython shows an
object through its `_repr_png_` / `_repr_html_`; a plain matplotlib Figure has neither, and a
FuncAnimation's gives nothing while rcParams["animation.html"] is "none", the default)."""

from __future__ import annotations

import io

from matplotlib import rcParams
from matplotlib.animation import FuncAnimation
from matplotlib.figure import Figure


class ShownFigure(Figure):
    """A matplotlib Figure that shows itself in a notebook as a PNG at its size and dpi."""

    def _repr_png_(self) -> bytes:
        buffer = io.BytesIO()
        self.savefig(buffer, format="png")
        return buffer.getvalue()


class ShownAnimation(FuncAnimation):
    """A FuncAnimation that shows itself in a notebook: as rcParams["animation.html"] asks ("html5",
    "jshtml"), else as the JavaScript player of `to_jshtml()` (its frames embedded: works offline)."""

    def _repr_html_(self) -> str:
        if rcParams["animation.html"] != "none":
            return super()._repr_html_()
        return self.to_jshtml()
