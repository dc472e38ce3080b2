"""The demo output folder's ``index.html``: the video, the trajectory plot and the summary side
by side, so a run opens in a browser. The page links the files by their names in the folder, so
the folder can be moved or copied whole."""
import html
import os
from typing import Mapping

PAGE_NAME = 'index.html'
PAGE = '''<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>{title}</title>
<style>
body {{ font-family: sans-serif; margin: 1em; }}
.run {{ display: flex; flex-wrap: wrap; gap: 1em; align-items: flex-start; }}
.run video, .run img {{ max-width: 100%; }}
.run figure {{ margin: 0; }}
table {{ border-collapse: collapse; }}
td, th {{ border: 1px solid #ccc; padding: 0.2em 0.6em; text-align: left; }}
</style>
</head>
<body>
<h1>{title}</h1>
<div class="run">
<figure><video src="{video}" controls autoplay muted loop playsinline></video>
<figcaption>annotated camera and top-down view (<a href="{video}">{video}</a>)</figcaption></figure>
<figure><img src="{plot}" alt="trajectory"><figcaption>trajectory</figcaption></figure>
<figure><table>
{rows}
</table><figcaption><a href="{summary}">{summary}</a></figcaption></figure>
</div>
</body>
</html>
'''


def _cell(value) -> str:
    if isinstance(value, float):
        return '%.3f' % value
    if isinstance(value, (list, tuple)):
        return ', '.join(_cell(item) for item in value)
    return 'n/a' if value is None else str(value)


def demo_page(summary: Mapping[str, object], video: str = 'demo.mp4',
              plot: str = 'trajectory.png', summary_file: str = 'summary.json') -> str:
    """The page's HTML: ``video`` and ``plot`` (names in the folder) next to a table of
    ``summary``'s fields, in its order, every text escaped."""
    title = 'can_seeker demo, seed %s: %s' % (summary.get('seed', '?'),
                                              'SUCCESS' if summary.get('success') else 'FAILED')
    rows = '\n'.join('<tr><th>%s</th><td>%s</td></tr>' % (html.escape(str(name)),
                                                        html.escape(_cell(value)))
                     for name, value in summary.items())
    return PAGE.format(title=html.escape(title), video=html.escape(video, quote=True),
                       plot=html.escape(plot, quote=True), rows=rows,
                       summary=html.escape(summary_file, quote=True))


def write_demo_page(folder: str, summary: Mapping[str, object], **names) -> str:
    """Write :func:`demo_page` to ``folder``/index.html; its path."""
    path = os.path.join(folder, PAGE_NAME)
    with open(path, 'w', encoding='utf-8') as output:
        output.write(demo_page(summary, **names))
    return path
