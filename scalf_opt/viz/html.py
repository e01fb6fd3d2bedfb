"""One self-contained HTML page: meshcat's bundled viewer, the scene's commands and a legend.

The page carries meshcat's viewer JavaScript (``meshcat/viewer/dist/main.min.js``, shipped inside
the meshcat Python package) inline, and the scene as base64-encoded msgpack commands that it
hands to ``viewer.handle_command_bytearray`` in order, exactly as a meshcat server would send
them over its websocket. It loads nothing from anywhere: no server, no CDN, no network.
"""

from __future__ import annotations

import base64
import html
import importlib.util
import json
from pathlib import Path

from scalf_opt.errors import ConfigError
from scalf_opt.viz.scene import POWER_COLORMAP, Scene

VIEWER_SCRIPT = Path("viewer") / "dist" / "main.min.js"
"""The viewer's JavaScript inside the meshcat package."""


def viewer_script() -> str:
    """The viewer JavaScript that meshcat ships.

    Raises:
        ConfigError: meshcat is not installed (``pip install 'scalf-opt[viz]'``).
    """
    spec = importlib.util.find_spec("meshcat")
    if spec is None or not spec.submodule_search_locations:
        raise ConfigError("the 3-D view needs meshcat: pip install 'scalf-opt[viz]'")
    path = Path(next(iter(spec.submodule_search_locations))) / VIEWER_SCRIPT
    try:
        script = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise ConfigError(f"{path}: meshcat's viewer script cannot be read ({exc})") from exc
    return script.replace("</script", "<\\/script")  # cannot end the inline <script> early


def scene_page(scene: Scene) -> str:
    """The HTML page of ``scene``."""
    commands = json.dumps([base64.b64encode(c).decode("ascii") for c in scene.commands])
    return _PAGE.format(
        title=html.escape(f"scalf-opt view: {scene.title}"),
        legend=legend_html(scene),
        viewer=viewer_script(),
        commands=commands,
    )


def legend_html(scene: Scene) -> str:
    """The legend: title, one row per trajectory, the power scale, how to use the view."""
    rows = [f"<div class='title'>{html.escape(scene.title)}</div>"]
    rows.append(
        "<div class='note'>robots from front to back, each on a strip of its colour; foot "
        f"paths of all four legs over {scene.n_cycles} gait cycles</div>"
    )
    for entry in scene.legend:
        # energies to the millijoule and powers to 10 mW, as the command line prints them
        legs = ", ".join(f"{leg} {e:.3f}" for leg, e in entry.leg_energy_j.items())
        rows.append(
            "<div class='row'>"
            f"<span class='swatch' style='background:{entry.color}'></span>"
            f"<span class='label'>{html.escape(entry.label)}</span>"
            f"<div class='numbers'>{entry.energy_j:.3f} J per cycle, "
            f"{entry.average_power_w:.2f} W; {html.escape(entry.leg_energy_kind)} [J]: {legs}"
            f" ({html.escape(entry.energy_model)})</div></div>"
        )
    if scene.color_by == "power":
        lo, hi = scene.power_range_w
        rows.append(
            "<div class='row'>leg power along the swing paths "
            f"({html.escape(scene.power_note)})"
            f"<div class='scale' style='background:{_css_gradient()}'></div>"
            f"<div class='ends'><span>{lo:.3g} W</span><span>{hi:.3g} W</span></div></div>"
        )
    speed = "real time" if scene.playback_speed == 1.0 else f"{scene.playback_speed:g} x real time"
    rows.append(
        f"<div class='note'>animation: {speed}, looping (Open Controls, Animations: pause, "
        "scrub, time scale; add #t=0.5 to the address for a still at 0.5 s); drag to orbit, "
        "right-drag to pan, scroll to zoom</div>"
    )
    if scene.skipped_visuals:
        rows.append(
            "<div class='note'>not drawn (geometry type unsupported): "
            f"{html.escape(', '.join(scene.skipped_visuals))}</div>"
        )
    return "\n".join(rows)


def _css_gradient() -> str:
    from matplotlib import colormaps

    cmap = colormaps[POWER_COLORMAP]
    stops = []
    for k in range(11):
        r, g, b, _ = cmap(k / 10)
        stops.append(f"rgb({round(255 * r)},{round(255 * g)},{round(255 * b)}) {10 * k}%")
    return f"linear-gradient(to right, {', '.join(stops)})"


_PAGE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>{title}</title>
<style>
body {{ margin: 0; font-family: sans-serif; }}
#meshcat-pane {{ width: 100vw; height: 100vh; overflow: hidden; }}
#scalf-legend {{ position: absolute; left: 8px; top: 8px; max-width: 380px; padding: 6px 9px;
  background: rgba(255, 255, 255, 0.88); border-radius: 6px; font-size: 12px; color: #222; }}
#scalf-legend .title {{ font-weight: bold; margin-bottom: 4px; }}
#scalf-legend .row {{ margin-top: 6px; }}
#scalf-legend .swatch {{ display: inline-block; width: 14px; height: 14px; margin-right: 6px;
  vertical-align: middle; border-radius: 2px; }}
#scalf-legend .label {{ font-weight: bold; vertical-align: middle; }}
#scalf-legend .numbers {{ margin-left: 20px; }}
#scalf-legend .note {{ color: #555; font-size: 11px; margin-top: 4px; }}
#scalf-legend .scale {{ height: 10px; margin-top: 3px; }}
#scalf-legend .ends {{ display: flex; justify-content: space-between; font-size: 11px; }}
</style>
</head>
<body>
<div id="meshcat-pane"></div>
<div id="scalf-legend">
{legend}
</div>
<script>
{viewer}
</script>
<script>
var viewer = new MeshCat.Viewer(document.getElementById("meshcat-pane"));
(function () {{
  var commands = {commands};
  for (var i = 0; i < commands.length; i++) {{
    var text = atob(commands[i]);
    var bytes = new Uint8Array(text.length);
    for (var k = 0; k < text.length; k++) bytes[k] = text.charCodeAt(k);
    viewer.handle_command_bytearray(bytes);
  }}
  // scene.html#t=0.75: paused at 0.75 s of the animation (a still, for screenshots and links)
  var still = /[#&]t=([0-9]*[.]?[0-9]+)/.exec(window.location.hash);
  if (still) {{
    viewer.animator.pause();
    viewer.animator.seek(parseFloat(still[1]));
  }}
}})();
</script>
</body>
</html>
"""
