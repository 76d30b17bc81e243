"""The README's Python examples run as written (in a folder with the finger they name)."""
import os
import re
import subprocess

README = os.path.join(os.path.dirname(__file__), "..", "..", "README.md")
BIN = os.environ.get("DF_BIN", os.path.join(os.path.dirname(__file__), "..", "..", "build", "bin"))


def test_readme_python_examples(tmp_path, monkeypatch):
    text = open(README).read()
    section = text[text.index("## Python"):]
    section = section[:section.index("\n## ", 3)]
    blocks = re.findall(r"```python\n(.*?)```", section, re.S)
    assert len(blocks) == 3
    subprocess.run([os.path.join(BIN, "synth-meshseq"), "-q", "--frames", "8", "--resolution", "6", "-o",
                    str(tmp_path / "finger.h5")], check=True)
    monkeypatch.chdir(tmp_path)
    scope = {}
    for code in blocks:
        exec(compile(code, "README.md", "exec"), scope)  # one session, as a reader would type it
    assert scope["df"].erms(scope["back"], scope["verts"]) < 1e-3
    assert (tmp_path / "mine.h5").exists()
