/* vi_bad_scenes.h - malformed scenes shared by test_scene and test_app. */
#ifndef VI_BAD_SCENES_H
#define VI_BAD_SCENES_H

/* A malformed scene, the stage that must reject it, the code, line, key. */
typedef struct bad {
  const char *what, *text;
  int code, line;
  const char *key;
} bad;

#define GOOD_STOP "stop: {mass: 2, xs: 0.1, r: 0.7}\n"
#define CHAIN "model:\n  chain: {n: 2, m: 1, k: 1, c: 0.1}\n"

static const bad cases[] = {
  {"YAML syntax", CHAIN "forcing: {omega: 0.9, a: [0.5, 0.0}\n" GOOD_STOP, VI_ERR_PARSE, 3, ""},
  {"unknown top key", CHAIN GOOD_STOP "solver: cvode\n", VI_ERR_PARSE, 4, "solver"},
  {"misspelt key", CHAIN "forcing: {omgea: 0.9}\n" GOOD_STOP, VI_ERR_PARSE, 3, "forcing.omgea"},
  {"wrong type", CHAIN "forcing: {omega: fast}\n" GOOD_STOP, VI_ERR_PARSE, 3, "forcing.omega"},
  {"wrong length", CHAIN "forcing: {omega: 0.9, a: [0.5, 0.0, 1.0]}\n" GOOD_STOP, VI_ERR_DIM, 3, "forcing.a"},
  {"NaN", CHAIN "forcing: {omega: 0.9, a: [.nan, 0.0]}\n" GOOD_STOP, VI_ERR_PARSE, 3, "forcing.a[1]"},
  {"r = 1.5", CHAIN "stop: {mass: 2, xs: 0.1, r: 1.5}\n", VI_ERR_RESTITUTION, 3, "stop.r"},
  {"missing stop", CHAIN "forcing: {omega: 0.9}\n", VI_ERR_PARSE, 1, "stop"},
  {"missing r", CHAIN "stop: {mass: 2, xs: 0.1}\n", VI_ERR_PARSE, 3, "stop.r"},
  {"stop mass out of range", CHAIN "stop: {mass: 3, xs: 0.1, r: 0.7}\n", VI_ERR_PARSE, 3, "stop.mass"},
  {"negative tolerance", CHAIN GOOD_STOP "run: {rtol: -1.0e-8}\n", VI_ERR_TOLERANCE, 4, "run.rtol"},
  {"bad method", CHAIN GOOD_STOP "run: {method: rk4}\n", VI_ERR_PARSE, 4, "run.method"},
  {"t_end and periods", CHAIN GOOD_STOP "run: {t_end: 10, periods: 3}\n", VI_ERR_PARSE, 4, "run.periods"},
  {"non-square K", "model:\n  K: [[2, -1], [-1]]\n" GOOD_STOP, VI_ERR_DIM, 2, "model.K row 2"},
  {"two model kinds", "model:\n  K: [[1]]\n  chain: {n: 1, m: 1, k: 1}\nstop: {mass: 1, xs: 0.1, r: 0.7}\n", VI_ERR_PARSE, 2, "model"},
  {"duplicate key", CHAIN GOOD_STOP "stop: {mass: 1, xs: 0.1, r: 0.7}\n", VI_ERR_PARSE, 4, "stop"},
  {"not a mapping", "- 1\n- 2\n", VI_ERR_PARSE, 1, ""},
  {"boolean expected", CHAIN GOOD_STOP "forcing: {omega: 0.9}\noutput: {ledger: maybe}\n", VI_ERR_PARSE, 5, "output.ledger"},
  {"no frequency, no end time", CHAIN GOOD_STOP, VI_ERR_TIME, 1, "run.t_end"},
  {"empty file", "", VI_ERR_PARSE, 1, ""},
  {"rtol out of range", CHAIN GOOD_STOP "run: {rtol: 10}\n", VI_ERR_TOLERANCE, 4, "run.rtol"},
  {"quoted number", CHAIN "forcing: {omega: '0.9'}\n" GOOD_STOP, VI_ERR_PARSE, 3, "forcing.omega"},
  {"!!str number", CHAIN "forcing: {omega: !!str 0.9}\n" GOOD_STOP, VI_ERR_PARSE, 3, "forcing.omega"},
  {"second document", CHAIN GOOD_STOP "run: {t_end: 10}\n---\nname: x\n", VI_ERR_PARSE, 5, ""},
  {"name is a list", "name: [1, 2]\n" CHAIN GOOD_STOP, VI_ERR_PARSE, 1, "name"},
  {"masses 1e30 apart", "model:\n  chain: {n: 2, m: [1, 1.0e-30], k: 1}\n" GOOD_STOP "run: {t_end: 10}\n", VI_ERR_LIMIT, 2, "model.chain.m"},
  /* rejected when the model is built: the model's own validation */
  {"non-symmetric K", "model:\n  K: [[2, -1], [-0.5, 1]]\nstop: {w: [0, 1], xs: 0.1, r: 0.7}\nrun: {t_end: 10}\n", VI_ERR_NOT_SYMMETRIC, 2, "model.K"},
  {"non-SPD M", "model:\n  M: [[1, 2], [2, 1]]\n  K: [[2, -1], [-1, 1]]\nstop: {w: [0, 1], xs: 0.1, r: 0.7}\nrun: {t_end: 10}\n", VI_ERR_NOT_SPD, 2, "model"},
  {"zero stop vector", "model:\n  K: [[2, -1], [-1, 1]]\nstop: {w: [0, 0], xs: 0.1, r: 0.7}\nrun: {t_end: 10}\n", VI_ERR_STOP_VECTOR, 3, "stop"},
  /* ranges that need the model's frequencies and scales */
  {"Omega 1e-300", CHAIN "forcing: {omega: 1.0e-300, a: [0.5, 0]}\n" GOOD_STOP, VI_ERR_LIMIT, 3, "forcing.omega"},
  {"atol 1e10", CHAIN GOOD_STOP "forcing: {omega: 0.9}\nrun: {atol: 1.0e10}\n", VI_ERR_LIMIT, 5, "run.atol"},
  {"initial velocity 1e30", CHAIN GOOD_STOP "forcing: {omega: 0.9}\ninitial: {v: [1.0e30, 0]}\n", VI_ERR_LIMIT, 5, "initial.v"},
  /* built-in springs */
  {"spring type", CHAIN GOOD_STOP "springs:\n  - {type: quartic, i: 1, k3: 1}\n", VI_ERR_PARSE, 5, "springs[1].type"},
  {"spring coordinate", CHAIN GOOD_STOP "springs:\n  - {type: cubic, i: 3, k3: 1}\n", VI_ERR_PARSE, 5, "springs[1].i"},
  {"spring to itself", CHAIN GOOD_STOP "springs:\n  - {type: cubic, i: 1, j: 1, k3: 1}\n", VI_ERR_PARSE, 5, "springs[1].j"},
  {"bilinear without gap", CHAIN GOOD_STOP "springs:\n  - {type: bilinear, i: 2, k: 3}\n", VI_ERR_PARSE, 5, "springs[1].gap"},
  {"bilinear with negative k", CHAIN GOOD_STOP "springs:\n  - {type: bilinear, i: 2, k: -3, gap: 0.05}\n", VI_ERR_PARSE, 5, "springs[1].k"},
  {"cantilever clamped stop", "model:\n  cantilever: {modes: 2, omega1: 1, zeta: 0.05, xi_stop: 0}\nforcing: {omega: 0.85, base: 0.01}\nstop: {xs: 0.05, r: 0.2}\n", VI_ERR_ARG, 2, "model.cantilever"},
  {"cubic with k", CHAIN GOOD_STOP "springs:\n  - {type: cubic, i: 2, k: 3}\n", VI_ERR_PARSE, 5, "springs[1].k"},
  {"springs with exact", CHAIN GOOD_STOP "springs:\n  - {type: cubic, i: 2, k3: 3}\nrun: {t_end: 10, method: exact}\n", VI_ERR_UNSUPPORTED, 5, "springs[1]"},
  /* stops: a list */
  {"stops not a list", CHAIN "stops: {mass: 2, xs: 0.1, r: 0.7}\n", VI_ERR_PARSE, 3, "stops"},
  {"empty stops", CHAIN "stops: []\n", VI_ERR_PARSE, 3, "stops"},
  {"stop and stops", CHAIN GOOD_STOP "stops:\n  - {mass: 2, xs: 0.1, r: 0.7}\n", VI_ERR_PARSE, 5, "stops"},
  {"second stop's r", CHAIN "stops:\n  - {mass: 2, xs: 0.1, r: 0.7}\n  - {mass: 1, xs: 0.1, r: 2}\n", VI_ERR_RESTITUTION, 5, "stops[2].r"},
  {"second stop's mass", CHAIN "stops:\n  - {mass: 2, xs: 0.1, r: 0.7}\n  - {mass: 3, xs: 0.1, r: 0.7}\n", VI_ERR_PARSE, 5, "stops[2].mass"},
  {"second stop zero", "model:\n  K: [[2, -1], [-1, 1]]\nstops:\n  - {w: [0, 1], xs: 0.1, r: 0.7}\n  - {w: [0, 0], xs: 0.1, r: 0.7}\nrun: {t_end: 10}\n", VI_ERR_STOP_VECTOR, 5, "stops[2]"},
  /* stops by coordinate and direction; broadcast initial states */
  {"dof and mass", CHAIN "stop: {dof: 2, mass: 2, xs: 0.1, r: 0.7}\n", VI_ERR_PARSE, 3, "stop.dof"},
  {"dof and w", CHAIN "stop: {dof: 2, w: [0, 1], xs: 0.1, r: 0.7}\n", VI_ERR_PARSE, 3, "stop.dof"},
  {"dof out of range", CHAIN "stop: {dof: 0, xs: 0.1, r: 0.7}\n", VI_ERR_PARSE, 3, "stop.dof"},
  {"direction 0", CHAIN "stop: {dof: 2, direction: 0, xs: 0.1, r: 0.7}\n", VI_ERR_PARSE, 3, "stop.direction"},
  {"direction 2", CHAIN "stop: {dof: 2, direction: 2, xs: 0.1, r: 0.7}\n", VI_ERR_PARSE, 3, "stop.direction"},
  {"direction with w", CHAIN "stop: {w: [0, 1], direction: -1, xs: 0.1, r: 0.7}\n", VI_ERR_PARSE, 3, "stop.direction"},
  {"second stop's direction", CHAIN "stops:\n  - {dof: 2, xs: 0.1, r: 0.7}\n  - {dof: 1, direction: up, xs: 0.1, r: 0.7}\n", VI_ERR_PARSE, 5, "stops[2].direction"},
  {"initial.x text", CHAIN GOOD_STOP "initial: {x: zero}\n", VI_ERR_PARSE, 4, "initial.x"},
  {"initial.v wrong length", CHAIN GOOD_STOP "initial: {v: [1, 2, 3]}\n", VI_ERR_DIM, 4, "initial.v"},
  /* rejected when the run is configured */
  {"initial state beyond the stop", CHAIN GOOD_STOP "initial: {x: [0.0, 0.5]}\nrun: {t_end: 10}\n", VI_ERR_INITIAL_STATE, 4, "initial"},
};

#endif
