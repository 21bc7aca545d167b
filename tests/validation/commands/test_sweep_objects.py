"""A sweep over a scene whose fields hold objects (contact settings, obstacles, a force model with parameters) runs:
its cases' keys and records write those fields as the scene file does (issue 48's first finding)."""

import json

from validation.commands import main


def test_a_sweep_over_a_contact_scene_runs_every_case(tmp_path, capsys):
    assert main(["sweep", "floor", "eta=10,20", "nodes=6x6", "t_end=0.01", "--out", str(tmp_path)]) == 0
    records = [json.loads(p.read_text()) for p in sorted((tmp_path / "cases").glob("*.json"))]
    assert len(records) == 2 and {r["status"] for r in records} == {"finished"}
    assert all(isinstance(r["fields"]["contact"], dict) for r in records)  # as the scene file's [contact] table


def test_a_sweep_over_a_scene_file_with_a_force_model_table_runs(tmp_path, capsys):
    scene = tmp_path / "shell.toml"
    scene.write_text('scene = "hanging"\nnodes = [6, 6]\n[force_model]\nkind = "koiter"\nE = 2e5\nnu = 0.3\n'
                     'h = 0.001\n')
    assert main(["sweep", str(scene), "gamma=0.1,0.2", "t_end=0.01", "--out", str(tmp_path / "out")]) == 0
    records = [json.loads(p.read_text()) for p in sorted((tmp_path / "out" / "cases").glob("*.json"))]
    assert len(records) == 2 and {r["status"] for r in records} == {"finished"}
    assert records[0]["fields"]["force_model"] == {"kind": "koiter", "E": 2e5, "nu": 0.3, "h": 0.001}
