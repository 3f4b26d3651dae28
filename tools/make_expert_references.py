#!/usr/bin/env python3
"""Writes assets/experts/references.json: the scores of each expert's scripted run, the
reference the trainer's score card compares a session with (docs/trainer-window.md).

Each expert is a shipped scenario whose script is the expert manoeuvre. Its run is
recorded as a session (colosim run EXPERT --record FILE --score --json) and the file keeps
the scores with the session's scenario and final state hashes. free_insertion takes about
3-4 minutes of wall time. tests/trainer/scenario_run_test.cc (ExpertReferencesAreCurrent)
fails when the simulation no longer gives these scores: run this again then.

Usage: tools/make_expert_references.py build/app/colosim [OUT]   (OUT must not exist)
"""
import json
import os
import subprocess
import sys
import tempfile

# scenario -> the expert whose scripted run is its reference. sigmoid_push starts from the
# same alpha loop as sigmoid_untwist, whose script is the expert's (the paper's benchmark).
# free_insertion's script was written by a lumen-following controller: an automated
# expert, not a recorded clinician. free_insertion_attached_rectum has none (an older model
# kept for the shipped synthetic insertion).
REFERENCES = {
    "sigmoid_untwist": "sigmoid_untwist",
    "sigmoid_push": "sigmoid_untwist",
    "free_insertion": "free_insertion",
}


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    exe = sys.argv[1]
    here = os.path.dirname(os.path.abspath(__file__))
    out = sys.argv[2] if len(sys.argv) == 3 else os.path.join(here, "..", "assets", "experts", "references.json")
    if os.path.exists(out):
        sys.exit(f"{out}: exists (never overwritten); move it away first")
    experts = {}
    with tempfile.TemporaryDirectory() as tmp:
        for expert in sorted(set(REFERENCES.values())):
            session = os.path.join(tmp, expert + ".jsonl")
            command = [exe, "run", expert, "--record", session, "--score", "--json"]
            print("running", " ".join(command[1:]), file=sys.stderr)
            scores = json.loads(subprocess.run(command, check=True, capture_output=True, text=True).stdout)
            with open(session) as f:
                header = json.loads(f.readline())
                last = None
                for line in f:
                    last = line
            end = json.loads(last)
            version = subprocess.run([exe, "--version"], capture_output=True, text=True).stdout.strip()
            experts[expert] = {
                "command": f"colosim run {expert} --record SESSION --score --json",
                "scenario_hash": header["scenario_hash"],
                "final_state_hash": end["state_hash"],
                "colosim_version": version or header["colosim_version"],
                "scores": scores,
            }
    doc = {
        "format": "colosim-expert-references",
        "version": 1,
        "note": "Made by tools/make_expert_references.py: the scores of each expert's scripted run, "
                "recorded as a session; the score card of colosim train compares a session with them.",
        "references": REFERENCES,
        "experts": experts,
    }
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    with open(out, "x") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")
    print("wrote", out, file=sys.stderr)


if __name__ == "__main__":
    main()
