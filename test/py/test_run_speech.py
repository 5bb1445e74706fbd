"""Speech a person can hear: the paper's narrow_minimal scenario run by `scripts/run.sh
--speech`, with espeak-ng writing each utterance as a WAV in the run directory. Checks, against
sox's own reading of the files: one WAV per utterance said, each as long as the duration the
dialogue manager planned with (it measured its templates with espeak-ng at start); every cue's
words end before the crossing; no utterance starts before the previous one ended."""

import shutil
import subprocess

import pytest

from conftest import run_sh, said_lines, scenarios_of


def test_wav_files_and_cue_timing_agree(tmp_path, source_dir, port_base):
    for p in ("espeak-ng", "soxi"):
        if not shutil.which(p):
            pytest.fail(f"{p} is not installed (scripts/lib.sh installs espeak-ng and sox)")
    name = "narrow_minimal"
    run_sh(source_dir, tmp_path, source_dir / "config/scenarios" / f"{name}.yaml",
           port=port_base, args=("--speech",))
    d = tmp_path / name
    print(said_lines(d / "transcript.txt"))
    wavs = {f.name: float(subprocess.check_output(["soxi", "-D", str(f)], text=True))
            for f in sorted((d / "speech").glob("*.wav"))}
    print(wavs)
    s = scenarios_of(tmp_path / "summary.json")[name]
    said = [(h["id"], e) for h in s["humans"] for e in h["transcript"]
            if e["kind"] == "say" and e["delivery"] == "said"]
    bad = []
    if len(said) < 2:
        bad.append(f"expected round 1 and round 2 to be said, got {len(said)} utterances")
    if len(wavs) != len(said):
        bad.append(f"{len(wavs)} WAV files for {len(said)} utterances said")
    spans = []
    for hid, e in said:
        act = e["act"].lower()
        match = [f for f in wavs if f.endswith(f"_h{hid}_r{e['round']}_{act}.wav")]
        if len(match) != 1:
            bad.append(f"round {e['round']} {act}: WAV files {match}")
            continue
        dur = wavs[match[0]]
        print(f"round {e['round']} {act}: planned {e['speech_duration_s']:.3f} s, WAV "
              f"{dur:.3f} s, starts {e['speech_start_s']:.2f} s after the decision, lead "
              f"{e['lead_s']}")
        # Within 20 ms only if the dialogue manager measured its texts with espeak-ng.
        if abs(dur - e["speech_duration_s"]) > 0.02:
            bad.append(f"{match[0]}: {dur} s long, planned with {e['speech_duration_s']} s")
        if e["round"] in (1, 2) and not (e["lead_s"] is not None and e["lead_s"] > 0.0):
            bad.append(f"round {e['round']}: its words end {e['lead_s']} s before the crossing")
        start = e["t_s"] + e["speech_start_s"]
        spans.append((start, start + e["speech_duration_s"], act))
    spans.sort()
    for (s0, e0, a0), (s1, e1, a1) in zip(spans, spans[1:]):
        if s1 < e0 - 1e-6:
            bad.append(f"{a1} starts at {s1:.2f} s while {a0} is spoken until {e0:.2f} s")
    assert not bad
