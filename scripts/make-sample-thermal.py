#!/usr/bin/env python3
"""Writes thermal.pdb and thermal.cif: a made-up crystal structure of glutathione
(gamma-L-Glu-L-Cys-Gly, zwitterion) with two waters, for the thermal-ellipsoid loader.

Nothing here is measured data. The geometry is built from internal coordinates with textbook
bond lengths and angles (C-C 1.52, C-N 1.33-1.49, C=O 1.23-1.26, C-S 1.81, X-ray C-H 0.97,
N-H 0.86-0.89, S-H 1.20 A); the anisotropic displacements follow a rigid-body (TLS-like)
model: an isotropic translation, libration about the molecule's long axis and, smaller, about
the two others, plus extra motion of terminal atoms perpendicular to the bond to their parent.
So atoms far from the centre and at the ends of chains have larger, elongated ellipsoids.
Hydrogens ride on their parents with B = 1.2 (1.5 for NH3+ and SH) * B_eq(parent) and have no
ANISOU, as in a typical X-ray structure. U is written in 10^-4 A^2 (PDB) and A^2 (mmCIF) from
the same integers, so both files describe the same ellipsoids.

Usage: python3 scripts/make-sample-thermal.py  (writes data/samples/thermal.pdb and .cif)
"""

import math
import os

# ------------------------------------------------------------------------------------------
# small vector algebra


def add(a, b):
    return [a[i] + b[i] for i in range(3)]


def sub(a, b):
    return [a[i] - b[i] for i in range(3)]


def scale(a, s):
    return [x * s for x in a]


def dot(a, b):
    return sum(a[i] * b[i] for i in range(3))


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def norm(a):
    return math.sqrt(dot(a, a))


def unit(a):
    return scale(a, 1.0 / norm(a))


def place(a, b, c, bond, angle, torsion):
    """NeRF: the point d with |cd| = bond, angle bcd, dihedral abcd (degrees)."""
    angle, torsion = math.radians(angle), math.radians(torsion)
    bc = unit(sub(c, b))
    n = unit(cross(sub(b, a), bc))
    m = cross(n, bc)
    d2 = [-bond * math.cos(angle), bond * math.sin(angle) * math.cos(torsion),
          bond * math.sin(angle) * math.sin(torsion)]
    return add(c, add(scale(bc, d2[0]), add(scale(m, d2[1]), scale(n, d2[2]))))


def dihedral(a, b, c, d):
    b0, b1, b2 = sub(a, b), sub(c, b), sub(d, c)
    b1 = unit(b1)
    v = sub(b0, scale(b1, dot(b0, b1)))
    w = sub(b2, scale(b1, dot(b2, b1)))
    return math.degrees(math.atan2(dot(cross(b1, v), w), dot(v, w)))


# ------------------------------------------------------------------------------------------
# geometry: heavy atoms from a Z-matrix (name, element, bond to, angle with, dihedral with)

pos = {"N1": [0.0, 0.0, 0.0], "CA1": [1.49, 0.0, 0.0]}
pos["C1"] = place([0.0, 1.0, 0.0], pos["N1"], pos["CA1"], 1.53, 110.5, 0.0)

ZMATRIX = [
    # gamma-glutamyl: carboxylate, amine and side chain
    ("O11", "C1", "CA1", "N1", 1.25, 117.0, -20.0),
    ("O12", "C1", "CA1", "N1", 1.26, 117.5, 160.0),
    ("CB1", "CA1", "N1", "C1", 1.53, 110.5, -122.0),
    ("CG1", "CB1", "CA1", "N1", 1.52, 113.0, -65.0),
    ("CD1", "CG1", "CB1", "CA1", 1.51, 112.0, 175.0),
    ("OE1", "CD1", "CG1", "CB1", 1.235, 121.5, -40.0),
    ("N2", "CD1", "CG1", "CB1", 1.33, 116.0, 140.0),
    # cysteinyl
    ("CA2", "N2", "CD1", "CG1", 1.455, 122.0, 178.0),
    ("C2", "CA2", "N2", "CD1", 1.525, 110.0, -120.0),
    ("O2", "C2", "CA2", "N2", 1.23, 120.5, -45.0),
    ("N3", "C2", "CA2", "N2", 1.33, 116.5, 135.0),
    ("CB2", "CA2", "N2", "C2", 1.53, 110.5, -122.0),
    ("SG2", "CB2", "CA2", "N2", 1.81, 114.0, -60.0),
    # glycyl
    ("CA3", "N3", "C2", "CA2", 1.45, 121.5, 180.0),
    ("C3", "CA3", "N3", "C2", 1.52, 112.0, -80.0),
    ("O31", "C3", "CA3", "N3", 1.25, 117.0, 170.0),
    ("O32", "C3", "CA3", "N3", 1.26, 117.0, -10.0),
]
for name, c, b, a, bond, angle, torsion in ZMATRIX:
    pos[name] = place(pos[a], pos[b], pos[c], bond, angle, torsion)

# Hydrogens: (name, parent, angle atom, dihedral atom, bond, angle, dihedral).
HYDROGENS = [
    ("H1", "N1", "CA1", "C1", 0.89, 109.5, 60.0),
    ("H2", "N1", "CA1", "C1", 0.89, 109.5, 180.0),
    ("H3", "N1", "CA1", "C1", 0.89, 109.5, -60.0),
    ("HA1", "CA1", "N1", "C1", 0.98, 108.5, 118.0),
    ("HB11", "CB1", "CA1", "N1", 0.97, 108.8, -65.0 + 120.0),
    ("HB12", "CB1", "CA1", "N1", 0.97, 108.8, -65.0 - 120.0),
    ("HG11", "CG1", "CB1", "CA1", 0.97, 108.8, 175.0 + 120.0),
    ("HG12", "CG1", "CB1", "CA1", 0.97, 108.8, 175.0 - 120.0),
    ("HN2", "N2", "CD1", "CG1", 0.86, 119.0, -2.0),
    ("HA2", "CA2", "N2", "C2", 0.98, 108.5, 118.0),
    ("HB21", "CB2", "CA2", "N2", 0.97, 108.8, -60.0 + 120.0),
    ("HB22", "CB2", "CA2", "N2", 0.97, 108.8, -60.0 - 120.0),
    ("HSG", "SG2", "CB2", "CA2", 1.20, 96.0, 180.0),
    ("HN3", "N3", "C2", "CA2", 0.86, 119.0, 0.0),
    ("HA31", "CA3", "N3", "C2", 0.97, 109.0, -80.0 + 120.0),
    ("HA32", "CA3", "N3", "C2", 0.97, 109.0, -80.0 - 120.0),
]
for name, parent, b, a, bond, angle, torsion in HYDROGENS:
    pos[name] = place(pos[a], pos[b], pos[parent], bond, angle, torsion)

# L configuration at both alpha carbons: (C - CA) . ((CB - CA) x (N - CA)) > 0.
for n, ca, c, cb in [("N1", "CA1", "C1", "CB1"), ("N2", "CA2", "C2", "CB2")]:
    v = dot(sub(pos[c], pos[ca]), cross(sub(pos[cb], pos[ca]), sub(pos[n], pos[ca])))
    assert v > 0, f"{ca} is not L"

HEAVY = ["N1", "CA1", "C1", "O11", "O12", "CB1", "CG1", "CD1", "OE1",
         "N2", "CA2", "C2", "O2", "CB2", "SG2", "N3", "CA3", "C3", "O31", "O32"]
PARENT = {"O11": "C1", "O12": "C1", "OE1": "CD1", "O2": "C2", "SG2": "CB2",
          "O31": "C3", "O32": "C3", "N1": "CA1"}

# Two waters hydrogen-bonded to the carboxylates (O...O 2.75 A), pointing away from the molecule.
centroid = scale([sum(pos[a][i] for a in HEAVY) for i in range(3)], 1.0 / len(HEAVY))
HBOND = {"OW1": "O31", "OW2": "O11"}
for water, acceptor, parent in [("OW1", "O31", "C3"), ("OW2", "O11", "C1")]:
    away = unit(add(unit(sub(pos[acceptor], pos[parent])), scale(unit(sub(pos[acceptor], centroid)), 0.6)))
    pos[water] = add(pos[acceptor], scale(away, 2.75))

# Move the molecule into a crystal-like position: centroid at a point in a 5.61 x 8.81 x 28.18 cell.
shift = sub([2.9, 4.3, 7.6], centroid)
for k in pos:
    pos[k] = add(pos[k], shift)
centroid = add(centroid, shift)

# Sanity: no clashes. Atoms two or three bonds apart are at least 2.1 A apart, atoms further
# apart (and the waters) at least 2.7 A.
names = HEAVY + ["OW1", "OW2"]
bonds = {("N1", "CA1"), ("CA1", "C1")} | {(row[0], row[1]) for row in ZMATRIX}
within = {a: {a} for a in names}  # atoms within k bonds, k = 1, 2, 3 below
for a, b in bonds:
    within[a].add(b)
    within[b].add(a)
bonded = {a: set(within[a]) for a in names}
for _ in range(2):
    within = {a: set().union(*(bonded[b] for b in within[a])) for a in names}
for i, a in enumerate(names):
    for b in names[i + 1:]:
        d = norm(sub(pos[a], pos[b]))
        assert b in bonded[a] or d > (2.1 if b in within[a] else 2.7), (a, b, d)

# ------------------------------------------------------------------------------------------
# displacements: U = T + libration + terminal wobble (A^2)


def outer(a, b):
    return [[a[i] * b[j] for j in range(3)] for i in range(3)]


def madd(m, n, s=1.0):
    return [[m[i][j] + s * n[i][j] for j in range(3)] for i in range(3)]


def eye(s):
    return [[s if i == j else 0.0 for j in range(3)] for i in range(3)]


# Principal axes of the heavy-atom cloud by power iteration on the inertia-like tensor.
cov = [[0.0] * 3 for _ in range(3)]
for a in HEAVY:
    r = sub(pos[a], centroid)
    cov = madd(cov, outer(r, r))
long_axis = unit([1.0, 0.3, 0.2])
for _ in range(200):
    long_axis = unit([dot(cov[i], long_axis) for i in range(3)])
side = unit(cross(long_axis, [0.0, 0.0, 1.0]))
third = cross(long_axis, side)

T = madd(madd(eye(0.020), outer(side, side), 0.005), outer(third, third), 0.002)
LIBRATIONS = [(long_axis, 0.0045), (side, 0.0012), (third, 0.0010)]  # rad^2


def displacement(name):
    r = sub(pos[name], centroid)
    u = [row[:] for row in T]
    for axis, l2 in LIBRATIONS:
        v = cross(axis, r)
        u = madd(u, outer(v, v), l2)
    if name in PARENT:
        b = unit(sub(pos[name], pos[PARENT[name]]))
        wobble = 0.016 if name.startswith("O") else 0.010
        u = madd(u, madd(eye(wobble), outer(b, b), -wobble))
    if name in HBOND:
        # Waters: loosely held, flattened along their one hydrogen bond.
        h = unit(sub(pos[name], pos[HBOND[name]]))
        u = madd(u, madd(eye(0.022), outer(h, h), -0.018))
    return u


def positive_definite(m):
    d1 = m[0][0]
    d2 = m[0][0] * m[1][1] - m[0][1] * m[1][0]
    d3 = (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
          - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
          + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))
    return d1 > 0 and d2 > 0 and d3 > 0


anisou = {}
for name in names:
    u = displacement(name)
    ints = [round(1e4 * u[0][0]), round(1e4 * u[1][1]), round(1e4 * u[2][2]),
            round(1e4 * u[0][1]), round(1e4 * u[0][2]), round(1e4 * u[1][2])]
    m = [[ints[0], ints[3], ints[4]], [ints[3], ints[1], ints[5]], [ints[4], ints[5], ints[2]]]
    assert positive_definite(m), name
    anisou[name] = ints


def b_eq(ints):
    return 8 * math.pi ** 2 * (ints[0] + ints[1] + ints[2]) / 3 * 1e-4


# ------------------------------------------------------------------------------------------
# records

ELEMENT = lambda n: "S" if n.startswith("S") else ("H" if n.startswith("H") else n[0])
atoms = []  # (record, name, resname, resseq, element, xyz, B, anisou or None)
order = []
for name in HEAVY:
    order.append(name)
    order += [h[0] for h in HYDROGENS if h[1] == name]
for name in order:
    if name in anisou:
        b = b_eq(anisou[name])
    else:
        parent = next(h[1] for h in HYDROGENS if h[0] == name)
        b = (1.5 if parent in ("N1", "SG2") else 1.2) * b_eq(anisou[parent])
    atoms.append(("HETATM", name, "GSH", 1, ELEMENT(name), pos[name], b, anisou.get(name)))
for i, w in enumerate(["OW1", "OW2"]):
    atoms.append(("HETATM", "O", "HOH", 101 + i, "O", pos[w], b_eq(anisou[w]), anisou[w]))

here = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "samples")


def pdb_name(name, element):
    # Element right-justified in columns 13-14: one-letter elements start in column 14.
    return f" {name:<3}" if len(element) == 1 and len(name) < 4 else f"{name:<4}"


with open(os.path.join(here, "thermal.pdb"), "w") as f:
    f.write("HEADER    MADE-UP TEST STRUCTURE                  01-JAN-25   XTHM              \n")
    f.write("TITLE     GLUTATHIONE (GAMMA-GLU-CYS-GLY) DIHYDRATE, INVENTED COORDINATES AND       \n")
    f.write("TITLE    2 ANISOTROPIC DISPLACEMENTS FOR THE ELLIPSOID-SPLAT THERMAL LOADER          \n")
    f.write("REMARK   3 WRITTEN BY scripts/make-sample-thermal.py; NOT EXPERIMENTAL DATA.    \n")
    f.write("CRYST1    5.613    8.807   28.182  90.00  90.00  90.00 P 21 21 21    4          \n")
    for serial, (rec, name, res, seq, el, xyz, b, u) in enumerate(atoms, start=1):
        chain = "A" if res == "GSH" else "B"
        ident = f"{serial:5d} {pdb_name(name, el)} {res:>3} {chain}{seq:4d} "
        f.write(f"{rec:<6}{ident}   {xyz[0]:8.3f}{xyz[1]:8.3f}{xyz[2]:8.3f}{1.0:6.2f}{b:6.2f}"
                f"          {el:>2}  \n")
        if u is not None:
            f.write(f"ANISOU{ident} " + "".join(f"{v:7d}" for v in u) + f"      {el:>2}  \n")
    f.write("END                                                                             \n")

with open(os.path.join(here, "thermal.cif"), "w") as f:
    f.write("data_XTHM\n#\n")
    f.write("_struct.title 'Glutathione dihydrate: invented coordinates and anisotropic displacements'\n")
    f.write("_cell.length_a 5.613\n_cell.length_b 8.807\n_cell.length_c 28.182\n")
    f.write("_cell.angle_alpha 90.00\n_cell.angle_beta 90.00\n_cell.angle_gamma 90.00\n")
    f.write("_symmetry.space_group_name_H-M 'P 21 21 21'\n#\n")
    cols = ["group_PDB", "id", "type_symbol", "label_atom_id", "label_alt_id", "label_comp_id",
            "label_asym_id", "label_entity_id", "label_seq_id", "pdbx_PDB_ins_code", "Cartn_x",
            "Cartn_y", "Cartn_z", "occupancy", "B_iso_or_equiv", "pdbx_formal_charge",
            "auth_seq_id", "auth_comp_id", "auth_asym_id", "auth_atom_id", "pdbx_PDB_model_num"]
    f.write("loop_\n" + "".join(f"_atom_site.{c}\n" for c in cols))
    for serial, (rec, name, res, seq, el, xyz, b, u) in enumerate(atoms, start=1):
        chain = "A" if res == "GSH" else "B"
        f.write(f"{rec:<6} {serial:<3} {el:<2} {name:<5} . {res} {chain} {1 if res == 'GSH' else 2} . ? "
                f"{xyz[0]:8.3f} {xyz[1]:8.3f} {xyz[2]:8.3f} 1.00 {b:6.2f} ? {seq:<3} {res} {chain} "
                f"{name} 1\n")
    f.write("#\n")
    acols = ["id", "type_symbol", "pdbx_label_atom_id", "pdbx_label_alt_id", "pdbx_label_comp_id",
             "pdbx_label_asym_id", "pdbx_label_seq_id", "pdbx_PDB_ins_code", "U[1][1]", "U[2][2]",
             "U[3][3]", "U[1][2]", "U[1][3]", "U[2][3]", "pdbx_auth_seq_id", "pdbx_auth_comp_id",
             "pdbx_auth_asym_id", "pdbx_auth_atom_id"]
    f.write("loop_\n" + "".join(f"_atom_site_anisotrop.{c}\n" for c in acols))
    for serial, (rec, name, res, seq, el, xyz, b, u) in enumerate(atoms, start=1):
        if u is None:
            continue
        chain = "A" if res == "GSH" else "B"
        us = " ".join(f"{v / 1e4:7.4f}" for v in u)
        f.write(f"{serial:<3} {el:<2} {name:<5} . {res} {chain} . ? {us} {seq:<3} {res} {chain} {name}\n")
    f.write("#\n")

# Report for the person running this.
for name in names:
    u = anisou[name]
    print(f"{name:4s} Beq {b_eq(u):6.2f}  U {u}")
print("peptide dihedral CG1-CD1-N2-CA2:", round(dihedral(pos["CG1"], pos["CD1"], pos["N2"], pos["CA2"]), 1))
