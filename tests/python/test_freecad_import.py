"""The module imports and works inside FreeCAD's own interpreter (freecadcmd)."""
import json
import os
import shutil
import subprocess
import textwrap

from conftest import BUILD, EXAMPLES


def test_module_works_inside_freecadcmd(tmp_path):
    exe = shutil.which("freecadcmd")
    assert exe, "freecadcmd is not installed (scripts/setup.sh installs Debian's freecad)"
    out = tmp_path / "out.json"
    script = tmp_path / "probe.py"
    script.write_text(textwrap.dedent(f"""
        import sys, json
        sys.path.insert(0, {os.path.join(BUILD, 'python')!r})
        import FreeCAD
        import pteromys
        rep, flights = pteromys.evaluate({EXAMPLES[0]!r})
        with open({str(out)!r}, "w") as f:
            json.dump({{"freecad": FreeCAD.Version()[:2], "mass": rep["mass_kg"], "n": len(flights)}}, f)
    """))
    env = dict(os.environ, QT_QPA_PLATFORM="offscreen")
    r = subprocess.run([exe, str(script)], capture_output=True, text=True, timeout=300, env=env)
    assert out.exists(), f"freecadcmd did not run the probe:\n{r.stdout}\n{r.stderr}"
    res = json.loads(out.read_text())
    assert res["n"] == 6 and res["mass"] > 0
