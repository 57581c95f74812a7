# SPDX-License-Identifier: MIT
# How calls behave as Python calls: progress, cancellation, Ctrl-C, other threads, thread counts.
import threading
import time

import numpy as np
import pytest

import fabsynth

REGION, PIXEL = (0, 0, 40, 40), 0.05  # 800 x 800 pixels per slice


def test_progress_is_called_and_false_cancels():
    f = fabsynth.foam.Foam(density=0.2, radius=0.25, cell=3, seed=1)
    seen = []
    list(f.slices(np.linspace(0, 5, 40), REGION, 0.2, progress=lambda x, stage: seen.append((x, stage))))
    assert seen and seen[-1][0] == pytest.approx(1.0) and all(s == "slices" for _, s in seen)
    assert all(a <= b for (a, _), (b, _) in zip(seen, seen[1:]))
    with pytest.raises(fabsynth.Cancelled):
        list(f.slices(np.linspace(0, 5, 40), REGION, 0.2, progress=lambda x, stage: False))


def test_an_exception_in_the_callback_comes_back():
    class Stop(Exception):
        pass

    def progress(x, stage):
        raise Stop()

    with pytest.raises(Stop):
        fabsynth.fem.homogenize(np.ones((4, 4, 4)), progress=progress)


def test_ctrl_c_stops_a_long_call_within_a_second(interrupt):
    # the slicer reports after every batch of SLICES_PER_BATCH slices of 200 x 200 pixels, well under
    # 0.1 s here; 1 s after the start the child is inside it (the whole run takes minutes)
    rc, elapsed = interrupt("""
        import numpy as np, fabsynth
        f = fabsynth.foam.Foam(density=0.2, radius=0.25, cell=3, seed=1)
        print("started", flush=True)
        for img in f.slices(np.linspace(0, 100, 40000), (0, 0, 20, 20), 0.1):
            pass
    """, 1.0)
    assert rc == 3 and elapsed < 1.0, f"exit {rc}, took {elapsed:.2f} s to stop"


def test_a_second_thread_runs_while_the_first_works():
    f = fabsynth.foam.Foam(density=0.2, radius=0.25, cell=3, seed=1)
    done = threading.Event()

    def long_call():
        for _ in f.slices(np.linspace(0, 20, 200), REGION, PIXEL):
            pass
        done.set()

    worker = threading.Thread(target=long_call)
    worker.start()
    time.sleep(0.3)
    t0 = time.monotonic()
    inside = f.contains(np.random.default_rng(1).uniform(0, 10, (1000, 3)))
    short = time.monotonic() - t0
    assert not done.is_set(), "the long call ended before the short one could overlap it"
    assert short < 2.0 and inside.shape == (1000,)
    worker.join()


def test_results_do_not_depend_on_the_thread_count():
    f = fabsynth.foam.Foam(density=0.3, radius=0.2, cell=2, seed=5)
    pts = np.random.default_rng(2).uniform(0, 8, (5000, 3))
    before = fabsynth.num_threads()
    try:
        fabsynth.set_num_threads(1)
        one = (f.slice(2.5, REGION, 0.2, supersample=2), f.contains(pts))
        fabsynth.set_num_threads(2)
        assert fabsynth.num_threads() == 2
        two = (f.slice(2.5, REGION, 0.2, supersample=2), f.contains(pts))
    finally:
        fabsynth.set_num_threads(0)
    assert fabsynth.num_threads() == before
    assert np.array_equal(one[0], two[0]) and np.array_equal(one[1], two[1])
