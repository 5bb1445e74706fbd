// Headless text spy: prints every decoded message of the channels matching a regex, one line
// each, for robots without a display. Types are found by fingerprint in the coopnav types jar
// (lcm.spy.LCMTypeDatabase scans the classpath), fields are printed by reflection.
//
// Usage: java -cp lcm.jar:coopnav_lcmtypes.jar coopnav.tools.TextSpy [--url URL] [--channel RE]
//          [--count N] [--timeout-s S]
package coopnav.tools;

import java.io.DataInputStream;
import java.io.ByteArrayInputStream;
import java.lang.reflect.Array;
import java.lang.reflect.Field;
import java.lang.reflect.Modifier;
import java.util.concurrent.atomic.AtomicInteger;

import lcm.lcm.LCM;
import lcm.lcm.LCMDataInputStream;
import lcm.lcm.LCMSubscriber;
import lcm.spy.LCMTypeDatabase;

public class TextSpy implements LCMSubscriber {
  private final LCMTypeDatabase db = new LCMTypeDatabase();
  private final AtomicInteger printed = new AtomicInteger();
  private final int maxCount;

  TextSpy(int maxCount) { this.maxCount = maxCount; }

  public static void main(String[] args) throws Exception {
    String url = System.getenv("LCM_DEFAULT_URL");
    String channel = ".*";
    int count = -1;
    double timeoutS = -1;
    for (int i = 0; i < args.length; ++i) {
      switch (args[i]) {
        case "--url": url = args[++i]; break;
        case "--channel": channel = args[++i]; break;
        case "--count": count = Integer.parseInt(args[++i]); break;
        case "--timeout-s": timeoutS = Double.parseDouble(args[++i]); break;
        case "-h": case "--help":
          System.out.println("TextSpy [--url URL] [--channel REGEX] [--count N] [--timeout-s S]");
          return;
        default:
          System.err.println("unknown argument " + args[i]);
          System.exit(2);
      }
    }
    LCM lcm = (url == null || url.isEmpty()) ? new LCM() : new LCM(url);
    TextSpy spy = new TextSpy(count);
    lcm.subscribe(channel, spy);
    long end = timeoutS > 0 ? System.currentTimeMillis() + (long) (timeoutS * 1000) : Long.MAX_VALUE;
    while (System.currentTimeMillis() < end && (count < 0 || spy.printed.get() < count)) {
      Thread.sleep(10);
    }
    System.out.flush();
    System.exit(count >= 0 && spy.printed.get() < count ? 1 : 0);
  }

  @Override
  public synchronized void messageReceived(LCM lcm, String channel, LCMDataInputStream ins) {
    if (maxCount >= 0 && printed.get() >= maxCount) return;
    if (channel.equals("LCM_SELF_TEST")) return;
    try {
      byte[] data = new byte[ins.available()];
      ins.readFully(data);
      long fp = new DataInputStream(new ByteArrayInputStream(data)).readLong();
      Class<?> cls = db.getClassByFingerprint(fp);
      if (cls == null) {
        System.out.println(channel + " <unknown type, fingerprint " + Long.toHexString(fp) + ", "
            + data.length + " bytes>");
      } else {
        Object msg = cls.getConstructor(byte[].class).newInstance(data);
        StringBuilder sb = new StringBuilder();
        sb.append(channel).append(' ').append(cls.getSimpleName()).append(' ');
        format(msg, sb);
        System.out.println(sb);
      }
      printed.incrementAndGet();
      System.out.flush();
    } catch (Exception e) {
      System.out.println(channel + " <decode failed: " + e + ">");
    }
  }

  private static void format(Object o, StringBuilder sb) throws IllegalAccessException {
    if (o == null) { sb.append("null"); return; }
    Class<?> c = o.getClass();
    if (c.isArray()) {
      sb.append('[');
      int n = Array.getLength(o);
      for (int i = 0; i < n; ++i) {
        if (i > 0) sb.append(", ");
        format(Array.get(o, i), sb);
      }
      sb.append(']');
    } else if (o instanceof String) {
      sb.append('"').append(((String) o).replace("\"", "\\\"")).append('"');
    } else if (o instanceof Number || o instanceof Boolean || o instanceof Character) {
      sb.append(o);
    } else {
      sb.append('{');
      boolean first = true;
      for (Field f : c.getFields()) {
        int m = f.getModifiers();
        if (Modifier.isStatic(m)) continue;  // constants and LCM_FINGERPRINT
        if (!first) sb.append(", ");
        first = false;
        sb.append(f.getName()).append(": ");
        format(f.get(o), sb);
      }
      sb.append('}');
    }
  }
}
