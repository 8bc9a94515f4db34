"""KeyboardInterrupt (a real SIGINT handled by Python) stops a long run promptly."""

import _thread
import signal
import threading
import time

import pytest

import magbubble as mb

# 1 s of simulated time at 1 MHz: minutes of work, stopped after 0.3 s
LONG = {"run.duration": 1.0, "run.sample_interval": 1e-6}


def test_keyboard_interrupt_stops_a_run():
    # A process started in the background by a non-interactive shell inherits SIGINT ignored,
    # and then Python installs no handler and interrupt_main() does nothing: install Python's
    # own handler for this test, as an interactive session has it.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(0.3, _thread.interrupt_main)
    start = time.monotonic()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            mb.run("scenes/radial_only.toml", overrides=LONG, progress=False)
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)
    assert time.monotonic() - start < 5.0


def test_progress_callback_sees_simulated_time_and_can_stop_the_run():
    seen = []

    def stop_after_some(t, duration):
        seen.append((t, duration))
        if len(seen) >= 3:
            raise RuntimeError("enough")

    with pytest.raises(RuntimeError, match="enough"):
        mb.run("scenes/radial_only.toml", overrides=LONG, progress=stop_after_some)
    assert all(d == 1.0 for _, d in seen)
    assert seen[-1][0] > 0.0
    # the module still works afterwards
    assert mb.run("scenes/radial_only.toml", overrides={"run.duration": 1e-6}).status == "completed"
