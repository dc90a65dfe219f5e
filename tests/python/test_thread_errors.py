"""Errors of calls made at once from several threads on one device: each thread gets its own call's message."""
import threading

import pytest

import megavox


def test_each_thread_gets_its_own_error(selector, tmp_path):
    device = megavox.Device(selector)
    wrong = []

    def fail_often(i):
        missing = str(tmp_path / f"missing_{i}.mvx")
        for _ in range(40):
            with pytest.raises(megavox.IoError) as e:
                device.open(missing)
            if f"missing_{i}.mvx" not in str(e.value):
                wrong.append((i, str(e.value)))

    threads = [threading.Thread(target=fail_often, args=(i,)) for i in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not wrong, wrong[:3]
