"""A straightforward NumPy global temporal PCA with the Gavish-Donoho automatic rank: the yardstick
the C++ filter's accuracy and speed are compared with in the same benchmark run."""

import numpy as np


def gavish_donoho_omega(beta):
    return 0.56 * beta ** 3 - 0.95 * beta ** 2 + 1.82 * beta + 1.43


def pca_denoise(seq, rank="auto"):
    """seq: float32 (frames, height, width, channels). Channels share one temporal basis."""
    frames = seq.shape[0]
    x = seq.reshape(frames, -1).astype(np.float64)          # F x n: one column per (pixel, channel) series
    mean = x.mean(axis=0, keepdims=True)
    xc = x - mean
    gram = xc @ xc.T                                          # F x F
    values, vectors = np.linalg.eigh(gram)
    values, vectors = np.clip(values[::-1], 0, None), vectors[:, ::-1]
    if rank == "auto":
        n = xc.shape[1]
        m = min(frames - 1, n)
        s = np.sqrt(values[:m])
        beta = m / max(frames - 1, n)
        rank = int(np.sum(s > gavish_donoho_omega(beta) * np.median(s)))
    v = vectors[:, :rank]
    out = mean + v @ (v.T @ xc)
    return out.reshape(seq.shape).astype(np.float32), rank


if __name__ == "__main__":
    # Run as its own process so the benchmark can give NumPy its best OpenBLAS settings:
    #   numpy_pca.py IN.npy OUT.npy REPEATS  ->  prints {"seconds": best, "rank": k}
    import json
    import sys
    import time

    seq = np.load(sys.argv[1])
    best, out, rank = float("inf"), None, None
    for _ in range(int(sys.argv[3])):
        t0 = time.perf_counter()
        out, rank = pca_denoise(seq, "auto")
        best = min(best, time.perf_counter() - t0)
    np.save(sys.argv[2], out)
    print(json.dumps({"seconds": best, "rank": rank}))
