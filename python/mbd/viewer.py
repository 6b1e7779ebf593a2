"""The motion of a result in the offline viewer page that ``mbd animate RESULT.csv -o
out.html`` writes (three.js bundled in, nothing fetched), and inline in Jupyter."""

import html

from . import _mbd


class ViewerPage:
    """For a result whose columns are ``mbd simulate``'s (t, then every body's pose): the
    viewer page as text (``viewer_page()``), and the page inline in a notebook (Jupyter calls
    ``_repr_html_``: an iframe whose srcdoc is the page)."""

    def viewer_page(self, plot=None):
        """The self-contained HTML page of this motion, as ``mbd animate`` writes it; ``plot``:
        the column plotted when it opens (default: the first body's x); an unknown column raises
        KeyError naming the near matches, as ``result[name]``."""
        if plot is not None and plot not in self.columns:
            raise KeyError(self._unknown(plot))
        return _mbd.viewer_page(self._model_handle, list(self.columns), self.data, plot or "")

    def _repr_html_(self):
        page = html.escape(self.viewer_page(), quote=True)
        return (f'<iframe class="mbd-viewer" srcdoc="{page}" style="width: 100%; height: 520px; border: 0" '
                f'sandbox="allow-scripts"></iframe>')
