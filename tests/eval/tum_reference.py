#!/usr/bin/env python3
"""Reference numbers for tests/eval (not run by CTest; needs numpy).

Re-states the computations of TUM's BSD-licensed RGB-D benchmark tools
(associate.py, evaluate_ate.py, evaluate_rpe.py --fixed_delta with all pairs;
Copyright (c) 2013 Juergen Sturm, TUM) in Python 3 / numpy, independently of
the C++ evaluator, to produce the expected values of
EvalReference.MatchesTumScriptsOnRecordedFixture (test_eval.cpp).

  tum_reference.py make-estimate SEQ_DIR OUT N   # writes the fixture estimate
  tum_reference.py GROUNDTRUTH ESTIMATE          # prints the reference numbers
"""
import math
import random
import sys

import numpy as np


# TUM trajectory file -> {stamp: [tx ty tz qx qy qz qw]}
def read(fn):
    d = {}
    for line in open(fn):
        if not line.strip() or line[0] == '#': continue
        v = [float(x) for x in line.split()]
        d[v[0]] = v[1:8]
    return d


# evaluate_rpe.py transform44: pose -> 4x4 matrix (quaternion normalised)
def T44(l):
    t = l[0:3]; q = np.array(l[3:7], dtype=float); nq = q.dot(q)
    q *= math.sqrt(2.0/nq); q = np.outer(q, q)
    return np.array([[1-q[1,1]-q[2,2], q[0,1]-q[2,3], q[0,2]+q[1,3], t[0]],
                     [q[0,1]+q[2,3], 1-q[0,0]-q[2,2], q[1,2]-q[0,3], t[1]],
                     [q[0,2]-q[1,3], q[1,2]+q[0,3], 1-q[0,0]-q[1,1], t[2]],
                     [0,0,0,1.0]])


# associate.py: greedy by |dt|, each stamp once, strict < max_difference
def associate(first, second, offset, maxd):
    fk = list(first.keys()); sk = list(second.keys())
    pm = [(abs(a-(b+offset)), a, b) for a in fk for b in sk if abs(a-(b+offset)) < maxd]
    pm.sort(); m = []
    fs, ss = set(fk), set(sk)
    for d, a, b in pm:
        if a in fs and b in ss:
            fs.remove(a); ss.remove(b); m.append((a, b))
    m.sort(); return m


# evaluate_ate.py align(): SVD (Horn/Umeyama), reflection guard, no scale
def align(model, data):
    mz = model - model.mean(1); dz = data - data.mean(1)
    W = np.zeros((3,3))
    for c in range(model.shape[1]): W += np.outer(mz[:,c], dz[:,c])
    U, d, Vh = np.linalg.svd(W.transpose())
    S_ = np.matrix(np.identity(3))
    if np.linalg.det(U)*np.linalg.det(Vh) < 0: S_[2,2] = -1
    rot = U*S_*Vh; trans = data.mean(1) - rot*model.mean(1)
    err = rot*model + trans - data
    return np.sqrt(np.sum(np.multiply(err, err), 0)).A[0]


# evaluate_rpe.py find_closest_index (bisection keeping the closest visited)
def fci(L, t):
    b, e = 0, len(L); diff = abs(L[0]-t); best = 0
    while b < e:
        m = int((e+b)/2)
        if abs(L[m]-t) < diff: diff = abs(L[m]-t); best = m
        if t == L[m]: return m
        elif L[m] > t: e = m
        else: b = m+1
    return best


# evaluate_rpe.py evaluate_trajectory, fixed delta, max_pairs = 0 (all pairs)
def rpe(gt, est, delta, unit):
    sg = sorted(gt.keys()); se = sorted(est.keys())
    idx = se if unit == 's' else list(range(len(se)))
    pairs = []
    for i in range(len(se)):
        j = fci(idx, idx[i]+delta)
        if j != len(se)-1: pairs.append((i, j))
    gi = np.median([s-t for s, t in zip(sg[1:], sg[:-1])]); mx = 2*gi
    tr, ro = [], []
    for i, j in pairs:
        g0 = sg[fci(sg, se[i])]; g1 = sg[fci(sg, se[j])]
        if abs(g0-se[i]) > mx or abs(g1-se[j]) > mx: continue
        E = np.dot(np.linalg.inv(np.dot(np.linalg.inv(T44(est[se[i]])), T44(est[se[j]]))),
                   np.dot(np.linalg.inv(T44(gt[g0])), T44(gt[g1])))
        tr.append(np.linalg.norm(E[0:3,3]))
        ro.append(np.arccos(min(1, max(-1, (np.trace(E[0:3,0:3])-1)/2))))
    tr, ro = np.array(tr), np.array(ro)
    return dict(pairs=len(tr), trans_rmse=np.sqrt(tr.dot(tr)/len(tr)), trans_mean=tr.mean(), trans_median=np.median(tr),
                trans_std=tr.std(), trans_max=tr.max(), rot_rmse_deg=np.sqrt(ro.dot(ro)/len(ro))*180/np.pi,
                rot_mean_deg=ro.mean()*180/np.pi, rot_max_deg=ro.max()*180/np.pi)

def make_estimate(seq, out_path, n):
    """Groundtruth pose nearest each RGB frame, a random-walk drift and a
    change of world frame; written with the RGB timestamps."""
    random.seed(1)
    gt = read(seq + "/groundtruth.txt"); sg = sorted(gt.keys())
    rgb = [float(l.split()[0]) for l in open(seq + "/rgb.txt") if l[0] != '#']
    W = T44([0.3, -0.2, 1.0, 0.1, 0.2, 0.3, 0.927])
    drift = np.identity(4); out = []
    for t in rgb[:n]:
        g = T44(gt[sg[fci(sg, t)]])
        a = np.array([random.gauss(0, .003) for _ in range(3)])
        th = np.linalg.norm(a); K = np.array([[0,-a[2],a[1]],[a[2],0,-a[0]],[-a[1],a[0],0]])/th
        R = np.identity(3) + math.sin(th)*K + (1-math.cos(th))*K.dot(K)
        step = np.identity(4); step[0:3,0:3] = R; step[0:3,3] = [random.gauss(0, .002) for _ in range(3)]
        drift = drift.dot(step)
        P = W.dot(drift).dot(g)
        R = P[0:3,0:3]; w = math.sqrt(max(0, 1+R.trace()))/2
        q = [(R[2,1]-R[1,2])/(4*w), (R[0,2]-R[2,0])/(4*w), (R[1,0]-R[0,1])/(4*w), w]
        out.append("%.6f %.9f %.9f %.9f %.9f %.9f %.9f %.9f" % (t, P[0,3], P[1,3], P[2,3], *q))
    open(out_path, "w").write("# timestamp tx ty tz qx qy qz qw\n" + "\n".join(out) + "\n")

def reference(gt_path, est_path):
    gt = read(gt_path); est = read(est_path)
    m = associate(gt, est, 0.0, 0.02)
    fx = np.matrix([[gt[a][i] for i in range(3)] for a, b in m]).transpose()
    sx = np.matrix([[est[b][i] for i in range(3)] for a, b in m]).transpose()
    e = align(sx, fx)
    ref = {"ate.poses": len(e), "ate.rmse": np.sqrt(e.dot(e)/len(e)), "ate.mean": e.mean(),
           "ate.median": np.median(e), "ate.std": e.std(), "ate.min": e.min(), "ate.max": e.max()}
    for key, (d, u) in {"rpe_1s": (1.0, 's'), "rpe_1frame": (1, 'f')}.items():
        for k2, v in rpe(gt, est, d, u).items(): ref[key + "." + k2] = float(v)
    return ref

if __name__ == "__main__":
    if sys.argv[1] == "make-estimate":
        make_estimate(sys.argv[2], sys.argv[3], int(sys.argv[4]))
    else:
        for k, v in reference(sys.argv[1], sys.argv[2]).items():
            print('      {"%s", %.12g},' % (k, v))
