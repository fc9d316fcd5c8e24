"""A render releases the GIL: Python keeps running beside it, and Ctrl-C stops it."""

import signal
import subprocess
import sys
import textwrap
import threading
import time

from conftest import same_bits

import prism


def test_python_keeps_running_while_a_thread_renders():
    scene = prism.builtin("sphereflake:3")
    settings = {"width": 320, "height": 240, "spp": 4, "threads": 1}
    result = {}

    def work():
        result["image"], _ = scene.render(**settings)

    worker = threading.Thread(target=work)
    ticks = 0
    worker.start()
    # Counting while the render runs: with the GIL held by the render, this loop could
    # not run until it finished, and `ticks` would stay near 0.
    while worker.is_alive():
        ticks += 1
        time.sleep(0.001)
    worker.join()
    assert ticks >= 20, f"the main thread ran only {ticks} times during the render"
    alone, _ = scene.render(**settings)
    assert same_bits(result["image"], alone)


def test_ctrl_c_interrupts_a_long_render():
    script = textwrap.dedent(
        """
        import signal, sys, prism
        # A job a non-interactive shell starts in the background inherits SIGINT ignored,
        # and Python then keeps ignoring it; a terminal's Ctrl-C, which this test stands
        # for, reaches a process that has the default handler.
        signal.signal(signal.SIGINT, signal.default_int_handler)
        scene = prism.builtin("sphereflake")
        print("rendering", flush=True)
        try:
            scene.render(width=4000, height=4000, spp=64, threads=1)
        except KeyboardInterrupt:
            print("interrupted", flush=True)
            sys.exit(3)
        print("finished", flush=True)
        """
    )
    child = subprocess.Popen(
        [sys.executable, "-c", script], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    assert child.stdout.readline().strip() == "rendering"
    time.sleep(0.5)
    child.send_signal(signal.SIGINT)
    # The render would take hours; a minute is only a bound on waiting for the answer.
    try:
        out, err = child.communicate(timeout=60)
    finally:
        child.kill()
    assert child.returncode == 3, (out, err)
    assert out.strip() == "interrupted"
