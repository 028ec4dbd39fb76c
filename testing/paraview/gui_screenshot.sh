#!/usr/bin/env bash
# Takes testing/paraview/gui_screenshot.png (README): the ParaView GUI with the plugin, after the GUI test's
# steps plus selecting the sphere. Not part of ctest (it looks at the whole screen).
#   PV_PLUGIN_DIR=<build>/lib/x86_64-linux-gnu/paraview-5.11/plugins/WhittedView ./gui_screenshot.sh [out.png]
# Needs xvfb-run, xwd (x11-apps) and ImageMagick's convert.
# WAIT (default 90 s): the playback and the last still frame must be done (45 s caught an interactive frame
# half traced on a loaded 2-core machine).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
out="${1:-$here/gui_screenshot.png}"
plugin_dir="${PV_PLUGIN_DIR:?set PV_PLUGIN_DIR to the folder holding WhittedView.so}"
script="$(mktemp --suffix=.xml)"
# The GUI test's events, then a click on the sphere's name in the pipeline browser (no --exit: the GUI stays).
# Then scroll the Properties panel down to the sphere's "Whitted Material" group.
scroll="${SCROLL:-380}"
browser="pqClientMainWindow/pipelineBrowserDock/pipelineBrowser"
scrollbar="pqClientMainWindow/propertiesDock/propertiesPanel/scrollArea/qt_scrollarea_vcontainer/1QScrollBar0"
sed "s#</pqevents>#  <pqevent object=\"$browser\" command=\"mousePress\" arguments=\"1,1,0,70,9,/0:0/0:0\" />\n  <pqevent object=\"$browser\" command=\"mouseRelease\" arguments=\"1,0,0,70,9,/0:0/0:0\" />\n  <pqevent object=\"$scrollbar\" command=\"set_int\" arguments=\"$scroll\" />\n</pqevents>#" \
  "$here/gui_whitted.xml" >"$script"
xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" bash -c '
  paraview -geometry 1280x1024+0+0 --dr --plugin-search-paths="$1" --plugins=WhittedView --test-script="$2" &
  pid=$!
  sleep "${WAIT:-90}"
  xwd -root -silent | convert xwd:- -crop "${CROP:-1280x1024+0+0}" +repage "$3"
  kill "$pid"; wait "$pid" 2>/dev/null || true' _ "$plugin_dir" "$script" "$out"
rm -f "$script"
echo "wrote $out"
