#!/usr/bin/env python3
"""Peer for `ramtk calib robot`: a plain numpy kinematic calibration written from the textbook
(DH + beta link transform, Gauss-Newton with a forward-difference Jacobian, the unidentifiable
parameters dropped by hand as the literature lists them), run side by side on the same file.

    bench/robot_calibration_peer.py ROBOT.yaml DATA.csv RAMTK_BINARY [--repeat N]

DATA.csv is the points form `ramtk simulate robot-calibration` writes (pose,q1..q6 deg,x,y,z mm).
Prints each side's wall time, the fit RMS per coordinate and the ratio. No timing is asserted.
"""
import subprocess, sys, time, tempfile
import numpy as np
import yaml


def link(d, th, a, al, be):
    n = len(th)
    one = np.ones(n)
    ct, st = np.cos(th), np.sin(th)
    ca, sa, cb, sb = np.cos(al) * one, np.sin(al) * one, np.cos(be) * one, np.sin(be) * one
    T = np.zeros((n, 4, 4))
    T[:, 0] = np.stack([ct * cb - sa * st * sb, -st * ca, ct * sb + sa * st * cb, a * ct], 1)
    T[:, 1] = np.stack([st * cb + sa * ct * sb, ct * ca, st * sb - ct * sa * cb, a * st], 1)
    T[:, 2] = np.stack([-ca * sb, sa, ca * cb, d * one], 1)
    T[:, 3, 3] = 1
    return T


def rotvec(w):
    t = np.linalg.norm(w)
    if t < 1e-15:
        return np.eye(3)
    k = w / t
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(t) * K + (1 - np.cos(t)) * K @ K


def peer(robot_path, data_path):
    robot = yaml.safe_load(open(robot_path))
    nom = np.array([[j['d'], np.radians(j['theta0']), j['a'], np.radians(j['alpha']), np.radians(j.get('beta', 0))]
                    for j in robot['joints']])
    raw = np.loadtxt(data_path, delimiter=',', skiprows=1)
    Q, P = np.radians(raw[:, 1:7]), raw[:, 7:10]

    def predict(x):
        dh = nom + x[:30].reshape(6, 5)
        T = np.tile(np.eye(4), (len(Q), 1, 1))
        for i in range(6):
            T = T @ link(dh[i, 0], dh[i, 1] + Q[:, i], dh[i, 2], dh[i, 3], dh[i, 4])
        pf = T[:, :3, :3] @ x[36:39] + T[:, :3, 3]
        return pf @ (rotvec(x[30:33]) @ R0).T + x[33:36]

    # Start: the set-up by Kabsch on a tool guess.
    global R0
    R0 = np.eye(3)
    x = np.zeros(39)
    x[36:39] = [0, 0, 100.0]
    pf = predict(x)
    ca, cb = pf.mean(0), P.mean(0)
    U, S, Vt = np.linalg.svd((pf - ca).T @ (P - cb))
    R0 = Vt.T @ np.diag([1, 1, np.sign(np.linalg.det(Vt.T @ U.T))]) @ U.T
    x[33:36] = cb - R0 @ ca
    # Free: DH d, theta, a, alpha of joints 1..5 less d1, theta1 (base), beta on parallel pairs,
    # one of d2..d4 (parallel axes), the set-up.
    free = []
    for i in range(6):
        for k in range(5):
            parallel = abs(np.sin(nom[i, 3])) < 0.17
            if i == 5 or (i == 0 and k in (0, 1)) or (k == 4 and not parallel) or (k == 0 and i in (2, 3)):
                continue
            free.append(5 * i + k)
    free += list(range(30, 39))
    for it in range(15):
        r = (predict(x) - P).ravel()
        J = np.empty((len(r), len(free)))
        for c, i in enumerate(free):
            xp = x.copy()
            xp[i] += 1e-7
            J[:, c] = ((predict(xp) - P).ravel() - r) / 1e-7
        dx = np.linalg.lstsq(J, -r, rcond=None)[0]
        x[free] += dx
        if np.abs(dx).max() < 1e-10:
            break
    r = predict(x) - P
    return np.sqrt((r ** 2).mean())


def main():
    robot, data, binary = sys.argv[1:4]
    repeat = int(sys.argv[sys.argv.index('--repeat') + 1]) if '--repeat' in sys.argv else 3
    for rep in range(repeat):
        t0 = time.time()
        rms_peer = peer(robot, data)
        t_peer = time.time() - t0
        with tempfile.TemporaryDirectory() as out:
            t0 = time.time()
            text = subprocess.run([binary, 'calib', 'robot', '--robot', robot, '--data', data, '--out', out + '/c',
                                   '--no-cyclic', '--no-compliance', '--folds', '2'],
                                  check=True, capture_output=True, text=True).stdout
            t_ramtk = time.time() - t0
        line = next(l for l in text.splitlines() if 'calibrated (fit)' in l)
        print(f'rep {rep}: ramtk {t_ramtk:.2f} s (whole process, with 2-fold held-out) [{line.split("RMS per coordinate")[1].split("mm")[0].strip()} mm]'
              f'   numpy peer {t_peer:.2f} s [{rms_peer:.5f} mm]   ratio peer/ramtk {t_peer / t_ramtk:.1f}')


if __name__ == '__main__':
    main()
