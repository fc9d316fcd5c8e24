"""A progress bar over tiles for a terminal, on standard error: no dependency, one line
redrawn in place, and nothing at all when standard error is not a terminal."""

import sys
import time


class TileBar:
    """Call `update(done, total)` as tiles arrive and `close()` at the end."""

    def __init__(self, label="tiles", stream=None, width=30):
        self.label = label
        self.stream = stream or sys.stderr
        self.width = width
        self.start = time.monotonic()
        self.live = hasattr(self.stream, "isatty") and self.stream.isatty()

    def update(self, done, total):
        if not self.live or total <= 0:
            return
        filled = round(self.width * done / total)
        elapsed = time.monotonic() - self.start
        left = elapsed / done * (total - done) if done else 0.0
        bar = "#" * filled + "-" * (self.width - filled)
        self.stream.write(
            f"\r{self.label} [{bar}] {done}/{total}  {elapsed:5.1f} s, ~{left:4.1f} s left"
        )
        self.stream.flush()

    def close(self):
        if self.live:
            self.stream.write("\n")
            self.stream.flush()
