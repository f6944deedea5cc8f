"""Results files written from Python: what a report or a resumed run would refuse (an edited
spec, a record of no episode this benchmark runs) is refused when written, and a report of a
file that does not exist is an error, not an empty table."""

import json

import pytest

from libero_vifo import _native


def test_edited_specs_and_records_are_refused_when_written(tmp_path):
    _, spec = _native.episode_specs(suites=["libero_goal"], protocols=["original"], episodes=1)[0]
    edited = json.dumps({**json.loads(spec), "seed": json.loads(spec)["seed"] ^ 1})
    with pytest.raises(ValueError, match="its seed differs from the one vifo makes"):
        _native.run_specs([edited], "zero", str(tmp_path / "a.jsonl"))
    _native.run_specs([spec], "zero", str(tmp_path / "a.jsonl"))
    line = (tmp_path / "a.jsonl").read_text().splitlines()[0]
    record = json.loads(line)
    results = _native.ResultsFile(str(tmp_path / "b.jsonl"), set="paper")
    # Locked while open (a second writer is refused); the lock file goes with the close.
    with pytest.raises(RuntimeError, match="another run is writing"):
        _native.ResultsFile(str(tmp_path / "b.jsonl"), set="paper")
    with pytest.raises(ValueError, match=r"initial state 999 \(the tasks have 50\)"):
        results.write(json.dumps({**record, "spec": {**record["spec"], "init": 999}}))
    results.write(line)
    results.close()
    assert (tmp_path / "b.jsonl").read_text() == line + "\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.jsonl", "b.jsonl"]


def test_a_report_of_a_missing_file_is_an_error(tmp_path):
    with pytest.raises(ValueError, match="typo.jsonl: no such results file"):
        _native.write_report([str(tmp_path / "typo.jsonl")], str(tmp_path / "report"))
