"""The documents say what the scripts do: every option the README (and docs/*.md) quote for a
script, as in `scripts/run.sh --no-build --profile calibrated`, is one that script's --help
names (an option the script does not know would fail a new user at once). The scenario-format
example is loaded by node_world_sim_scenario_files_test
(ScenarioFiles.TheFormatDocumentsExampleLoads)."""

import re
import subprocess

STOPS = ("`", "\n\n", " #", "scripts/", ";", " | ", "&&", "\n```")


def quoted_options(source_dir):
    """(script, option, document) for each option quoted after scripts/<name>.sh, up to the
    end of the inline code span, a blank line, a shell comment or the next command."""
    out = set()
    for path in [source_dir / "README.md", *sorted((source_dir / "docs").glob("*.md"))]:
        text = path.read_text(encoding="utf-8")
        for m in re.finditer(r"scripts/([a-z_]+\.sh)", text):
            rest = text[m.end():]
            end = min([len(rest)] + [i for i in (rest.find(s) for s in STOPS) if i >= 0])
            for opt in re.findall(r"(?:^|[\s\[])(--[a-z][a-z0-9-]*|-j)\b", rest[:end]):
                out.add((m.group(1), opt, str(path.relative_to(source_dir))))
    return sorted(out)


def test_every_quoted_script_option_is_in_its_help(source_dir):
    quoted = quoted_options(source_dir)
    assert quoted, "no quoted script option found"
    helps, bad = {}, []
    for script, opt, where in quoted:
        if script not in helps:
            p = subprocess.run(["bash", str(source_dir / "scripts" / script), "--help"],
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                               timeout=10)
            helps[script] = p.stdout
            if p.returncode != 0:
                bad.append(f"scripts/{script} --help does not exit 0 (quoted in {where})")
        if not re.search(re.escape(opt) + r"\b", helps[script]):
            bad.append(f"{where} quotes scripts/{script} {opt}, which its --help does not name")
    print(f"checked {len(quoted)} quoted options:")
    print("\n".join("  " + " ".join(q) for q in quoted))
    assert not bad
