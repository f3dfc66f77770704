#!/usr/bin/env bash
# Runs a command under a private Xvfb display (the vkgi-view tests; GLFW needs an X server).
# xvfb-run -a takes the first display number without a lock file, and two runs starting at
# the same moment can pick the same one; a random first number makes that unlikely when
# several test runs share the machine (ctest itself runs the view tests one at a time).
set -euo pipefail
exec xvfb-run -a -n "$((100 + RANDOM % 800))" -s "-screen 0 1024x768x24 -nolisten tcp" "$@"
