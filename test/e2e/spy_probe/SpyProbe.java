// A Java agent for e2e_spy_test: started inside lcm-spy's own JVM (JAVA_TOOL_OPTIONS=
// -javaagent:spy_probe.jar=<out dir>), it reads what lcm-spy's window lists (every JTable's
// "Channel" and "Type" columns, as the user sees them) and takes a screenshot of the display.
// It only looks: lcm-spy itself is unchanged and is started by scripts/spy.sh as a user starts it.
//
// Writes <out>/spy_channels.tsv (channel TAB type, one row per listed channel; rewritten every
// second while lcm-spy runs) and <out>/spy.png (the screen, once channels are listed).
import java.awt.Component;
import java.awt.Container;
import java.awt.GraphicsEnvironment;
import java.awt.Rectangle;
import java.awt.Robot;
import java.awt.Window;
import java.io.File;
import java.io.PrintWriter;
import java.lang.instrument.Instrumentation;
import java.util.ArrayList;
import java.util.List;
import javax.imageio.ImageIO;
import javax.swing.JTable;
import javax.swing.SwingUtilities;
import javax.swing.table.TableModel;

public final class SpyProbe {
  private SpyProbe() {}

  public static void premain(String args, Instrumentation inst) {
    final File out = new File(args == null || args.isEmpty() ? "." : args);
    Thread t = new Thread(() -> watch(out), "coopnav-spy-probe");
    t.setDaemon(true);  // never keeps lcm-spy alive
    t.start();
  }

  private static void watch(File out) {
    boolean shot = false;
    int listedBefore = -1;
    while (true) {
      try {
        Thread.sleep(1000);
        List<String[]> rows = new ArrayList<>();
        SwingUtilities.invokeAndWait(() -> {
          for (Window w : Window.getWindows()) collect(w, rows);
        });
        File tsv = new File(out, "spy_channels.tsv");
        File tmp = new File(out, "spy_channels.tsv.tmp");
        try (PrintWriter pw = new PrintWriter(tmp, "UTF-8")) {
          for (String[] r : rows) pw.println(r[0] + "\t" + r[1]);
        }
        if (!tmp.renameTo(tsv)) System.err.println("spy probe: cannot write " + tsv);
        // The screenshot once the list has settled (the same rows two seconds running).
        if (!shot && !rows.isEmpty() && rows.size() == listedBefore) {
          Rectangle screen =
              GraphicsEnvironment.getLocalGraphicsEnvironment().getMaximumWindowBounds();
          ImageIO.write(new Robot().createScreenCapture(screen), "png", new File(out, "spy.png"));
          shot = true;
        }
        listedBefore = rows.size();
      } catch (InterruptedException e) {
        return;
      } catch (Exception e) {
        System.err.println("spy probe: " + e);
      }
    }
  }

  // Every table with "Channel" and "Type" columns: lcm-spy's channel list.
  private static void collect(Component c, List<String[]> rows) {
    if (c instanceof JTable) {
      TableModel m = ((JTable) c).getModel();
      int channel = -1, type = -1;
      for (int i = 0; i < m.getColumnCount(); ++i) {
        if ("Channel".equals(m.getColumnName(i))) channel = i;
        if ("Type".equals(m.getColumnName(i))) type = i;
      }
      if (channel >= 0 && type >= 0) {
        for (int r = 0; r < m.getRowCount(); ++r)
          rows.add(new String[] {String.valueOf(m.getValueAt(r, channel)),
                                 String.valueOf(m.getValueAt(r, type))});
      }
    }
    if (c instanceof Container)
      for (Component child : ((Container) c).getComponents()) collect(child, rows);
  }
}
