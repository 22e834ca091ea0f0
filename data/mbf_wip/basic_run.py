"""Run a GW-BASIC program under PC-BASIC (black box) and collect what it wrote.

Used by the experiments, the table generator and the differential tests.
"""
import os
import subprocess
import tempfile


def run_basic(lines, keys=None, inputs=None, timeout=600):
    """Run a program given as a list of BASIC lines (without line ends).

    keys: text fed as keyboard input; inputs: {filename: bytes} written to
    the working directory first.  Returns (stdout_text, {filename: bytes})
    with every file present in the directory after the run.
    """
    with tempfile.TemporaryDirectory(prefix="mbfrun") as d:
        with open(os.path.join(d, "PROG.BAS"), "wb") as f:
            f.write("".join(line + "\r\n" for line in lines).encode("latin-1"))
        for name, data in (inputs or {}).items():
            with open(os.path.join(d, name), "wb") as f:
                f.write(data)
        cmd = ["pcbasic", "PROG.BAS", "--interface=none", "-q",
               "--output=STDOUT", "--sound=False"]
        if keys is not None:
            with open(os.path.join(d, "keys.txt"), "wb") as f:
                f.write(keys.encode("latin-1"))
            cmd.append("--input=keys.txt")
        out = subprocess.run(cmd, cwd=d, stdin=subprocess.DEVNULL,
                             capture_output=True, timeout=timeout)
        files = {}
        for name in os.listdir(d):
            if name not in ("PROG.BAS", "keys.txt") and name not in (inputs or {}):
                with open(os.path.join(d, name), "rb") as f:
                    files[name] = f.read()
        return out.stdout.decode("latin-1"), files
