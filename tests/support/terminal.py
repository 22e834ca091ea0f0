"""A program in a pseudo-terminal, for the tests of what it does on a real terminal: keys in,
the raw screen bytes out, the terminal's modes before and after."""

from __future__ import annotations

import os
import select
import struct
import subprocess
import time


class Terminal:
    """argv run on a new pseudo-terminal of rows x cols, as its controlling terminal (so that
    Ctrl-C and Ctrl-Z signal it)."""

    def __init__(self, argv, directory, rows=24, cols=80):
        import fcntl
        import termios
        self.master, self.slave = os.openpty()
        fcntl.ioctl(self.slave, termios.TIOCSWINSZ, struct.pack("HHHH", rows, cols, 0, 0))
        self.modes_before = termios.tcgetattr(self.slave)
        env = {k: v for k, v in os.environ.items() if k not in ("COLUMNS", "LINES")}
        self.proc = subprocess.Popen(argv, stdin=self.slave, stdout=self.slave,
                                     stderr=self.slave, cwd=directory, env=env,
                                     preexec_fn=self._controlling_terminal)
        self.seen = b""

    @staticmethod
    def _controlling_terminal():
        """In the child: a session of its own whose terminal is the pty."""
        import fcntl
        import termios
        os.setsid()
        fcntl.ioctl(0, termios.TIOCSCTTY, 0)

    def wait_for(self, text: bytes, timeout: float = 20.0, after: int = 0) -> int:
        """Read the screen until `text` appears at or after byte `after`; where it begins."""
        deadline = time.monotonic() + timeout
        while text not in self.seen[after:]:
            left = max(0.0, deadline - time.monotonic())
            ready, _, _ = select.select([self.master], [], [], left)
            assert ready, f"waited for {text!r}; the screen shows {self.seen[-300:]!r}"
            try:
                self.seen += os.read(self.master, 4096)
            except OSError:              # the program has ended and closed the terminal
                break
        assert text in self.seen[after:], \
            f"waited for {text!r}; the screen shows {self.seen[-300:]!r}"
        return self.seen.index(text, after)

    def drain(self, seconds: float) -> None:
        """Read whatever the program writes for `seconds`."""
        deadline = time.monotonic() + seconds
        while (left := deadline - time.monotonic()) > 0:
            if select.select([self.master], [], [], left)[0]:
                try:
                    self.seen += os.read(self.master, 65536)
                except OSError:
                    return

    def press(self, keys: bytes) -> None:
        os.write(self.master, keys)

    def modes(self):
        import termios
        return termios.tcgetattr(self.slave)

    def close(self):
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait()
        os.close(self.master)
        os.close(self.slave)
