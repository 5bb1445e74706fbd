#!/usr/bin/env bash
# Opens lcm-spy with our types. Debian's lcm-spy launcher passes -Xincgc, which JDK 17 rejects,
# so we start the Java class ourselves. Needs a display (use the text spy on headless robots).
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
jar="$COOPNAV_BUILD_DIR/coopnav_lcmtypes.jar"
[ -f "$jar" ] || { echo "spy: $jar missing; build first (scripts/test.sh or scripts/run.sh)" >&2; exit 1; }
url="${LCM_DEFAULT_URL:-udpm://239.255.76.67:7667?ttl=0}"
exec env CLASSPATH="$jar" java -Djava.net.preferIPv4Stack=true -Xmx256m \
  -cp /usr/share/java/lcm.jar:/usr/share/java/jchart2d.jar lcm.spy.Spy --lcm-url="$url" "$@"
