#!/usr/bin/env bash
# Headless text spy: prints decoded messages, one per line.
#   scripts/textspy.sh [--url URL] [--channel REGEX] [--count N] [--timeout-s S]
# URL may be a log: file:///abs/path/run.lcm?speed=0
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
jar="$COOPNAV_BUILD_DIR/coopnav_lcmtypes.jar"
[ -f "$jar" ] || { echo "textspy: $jar missing; build first" >&2; exit 1; }
exec java -Djava.net.preferIPv4Stack=true -Xmx128m \
  -cp /usr/share/java/lcm.jar:/usr/share/java/jchart2d.jar:"$jar" coopnav.tools.TextSpy "$@"
