"""Malformed inputs never crash the driver: mutated text and .npy files
(random bytes, truncation, NUL bytes, overflowing numbers) give a verdict
(0/1) or a data error (65) with a message naming the file, never a signal."""
import os
import subprocess

import numpy as np
import pytest

DRIVER = os.environ["IGEA_DRIVER"]


def run(cwd, *args):
    return subprocess.run([DRIVER, *args], cwd=cwd, capture_output=True, timeout=60)


@pytest.fixture(scope="module")
def flight(tmp_path_factory):
    d = tmp_path_factory.mktemp("fuzz")
    rng = np.random.default_rng(5)
    S = rng.standard_normal((60, 5))
    np.savetxt(d / "S.txt", S, fmt="%.17g")
    np.savetxt(d / "dw.txt", S @ rng.standard_normal(5) * 0.1 + 0.01 * rng.standard_normal(60))
    np.save(d / "S.npy", S)
    return d


def test_mutated_text(flight):
    rng = np.random.default_rng(11)
    good = (flight / "S.txt").read_bytes()
    tokens = [b"\x00", b"nan", b"inf", b"1e999", b"-", b"1.2.3", b",,", b"#", b"\n", b"0x1p3",
              b"\xff\xfe", b" 7 ", b"\t", b"e5", b"--1"]
    for trial in range(150):
        data = bytearray(good)
        for _ in range(rng.integers(1, 4)):
            pos = int(rng.integers(0, len(data)))
            op = rng.integers(0, 3)
            if op == 0:
                data[pos:pos] = tokens[rng.integers(0, len(tokens))]
            elif op == 1:
                del data[pos:pos + int(rng.integers(1, 20))]
            else:
                data = data[:pos]
        (flight / "m.txt").write_bytes(bytes(data))
        r = run(flight, "eqerr", "--S", "m.txt", "--dw", "dw.txt", "--sigma", "0.01", "--json")
        assert r.returncode in (0, 1, 65, 70), (trial, r.returncode, r.stderr)
        if r.returncode == 65:
            assert b"m.txt" in r.stderr or b"dw.txt" in r.stderr, r.stderr
        if r.returncode in (65, 70):
            assert r.stdout == b""   # nothing half-written


def test_mutated_npy(flight):
    rng = np.random.default_rng(12)
    good = (flight / "S.npy").read_bytes()
    for trial in range(100):
        data = bytearray(good)
        pos = int(rng.integers(0, 128 if trial % 2 else len(data)))
        if trial % 3 == 0:
            data = data[:pos]
        else:
            data[pos] = int(rng.integers(0, 256))
        (flight / "m.npy").write_bytes(bytes(data))
        r = run(flight, "eqerr", "--S", "m.npy", "--dw", "dw.txt", "--sigma", "0.01")
        assert r.returncode in (0, 1, 65, 70), (trial, r.returncode, r.stderr)
        if r.returncode == 65:
            assert b"m.npy" in r.stderr or b"dw.txt" in r.stderr, r.stderr


def test_mutated_inputs_through_a_pipe(flight):
    """The same mutated file read from a pipe (standard input, read as it
    comes, spooled for eqerr's second pass) gives what the file gives."""
    rng = np.random.default_rng(13)
    for name in ("S.npy", "S.txt"):
        good = (flight / name).read_bytes()
        for trial in range(40):
            data = bytearray(good)
            pos = int(rng.integers(0, len(data)))
            if trial % 2:
                data = data[:pos]
            else:
                data[pos] = int(rng.integers(0, 256))
            ext = name[1:]
            (flight / ("p" + ext)).write_bytes(bytes(data))
            a = run(flight, "eqerr", "--S", "p" + ext, "--dw", "dw.txt", "--sigma", "0.01",
                    "--json")
            b = subprocess.run([DRIVER, "eqerr", "--S", "-", "--dw", "dw.txt", "--sigma",
                                "0.01", "--json"], cwd=flight, input=bytes(data),
                               capture_output=True, timeout=60)
            assert a.returncode in (0, 1, 65, 70), (name, trial, a.stderr)
            assert (b.returncode, b.stdout) == (a.returncode, a.stdout), \
                (name, trial, a.stderr, b.stderr)
