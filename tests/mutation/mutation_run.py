#!/usr/bin/env python3
"""Mutation run of the monohydra command line (docs/reliability.md, "Mutation run").

Generates mutants of the shipped models, bad command lines and faulty plugin
libraries, runs the monohydra binary on each with a timeout, and classifies
every case:

  crash         killed by a signal we did not send, exit >= 128 not caused by
                us, exit 70 or "internal error"
  hang          exceeded its timeout (killed)
  short-exit0   exit 0 but fewer steps/rows than asked
  lost-rows     a CSV whose last line is cut, or a failed run whose CSV lacks
                rows the summary or the message says were done
  refused       exit 1 or 2 with a message naming the file:line/field, the
                flag, the value, the file or the plugin
  refused-vague exit 1 or 2 with a message naming none of these
  ok            exit 0, complete (or the expected 130/143 after our signal)
  other         anything else (e.g. exit 3..127 except 70)

Standard library only.  Usage:

  python3 tests/mutation/mutation_run.py --bin build/bin/monohydra --out /tmp/mut \
      [--seed 20261130] [--models models] [--jobs 2] [--faulty-dir build/tests/faulty-plugins]

Writes OUT/cases.csv (one row per case), OUT/summary.txt and keeps the
mutants in OUT/mutants/ and, for the cases that are not ok/refused, their
outputs in OUT/work/.
"""
import argparse
import collections
import concurrent.futures
import csv
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import time

NUMBER_RE = re.compile(r'(?<![\w.\-])-?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?(?![\w.])')
KEY_RE = re.compile(r'([A-Za-z_][\w-]*):(?=\s)')
SUMMARY_RE = re.compile(r'steps:\s+(\d+) of (\d+) asked \(dt = ([^ ]+) s, t_end = ([^ ]+) s\)')
STEP_MSG_RE = re.compile(r'failed at t = [^ ]+ s, step (\d+)')
STOP_MSG_RE = re.compile(r'stopped at t = [^ ]+ s, step (\d+) of')
FILE_LINE_RE = re.compile(r'[\w./-]+\.yaml:\d+(:\d+)?:')
NUMBER_VALUES = ['0', '-1', '.nan', 'nan', '.inf', '1e300', '1e-300', '5e-324', '"abc"', '[1, 2]']
SHORT_T_END = 0.05


def split_comment(line):
    i = line.find(' #')
    if line.lstrip().startswith('#'):
        return '', line
    if i < 0:
        return line, ''
    return line[:i], line[i:]


def flow_value_end(s, start):
    """End of a flow-mapping value starting at start (stops at , or } at depth 0)."""
    depth = 0
    i = start
    while i < len(s):
        c = s[i]
        if c in '[{':
            depth += 1
        elif c in ']}':
            if depth == 0:
                return i
            depth -= 1
        elif c == ',' and depth == 0:
            return i
        i += 1
    return i


class Case:
    __slots__ = ('cid', 'group', 'kind', 'detail', 'argv', 'env', 'timeout', 'csv', 'report',
                 't_end', 'sig', 'sig_after', 'stdout_file', 'model', 'expect', 'result')

    def __init__(self, cid, group, kind, detail, argv, env=None, timeout=30, csv=None, report=None,
                 t_end=None, sig=None, sig_after=None, stdout_file=None, model=None, expect=None):
        self.cid, self.group, self.kind, self.detail = cid, group, kind, detail
        self.argv, self.env, self.timeout, self.csv, self.report = argv, env, timeout, csv, report
        self.t_end, self.sig, self.sig_after, self.stdout_file = t_end, sig, sig_after, stdout_file
        self.model, self.expect, self.result = model, expect, None


class Builder:
    def __init__(self, args):
        self.args = args
        self.rng = random.Random(args.seed)
        self.out = os.path.abspath(args.out)
        self.mdir = os.path.join(self.out, 'mutants')
        self.wdir = os.path.join(self.out, 'work')
        self.bin = os.path.abspath(args.bin)
        self.cases = []
        self.n = 0
        models_dir = args.models
        self.models = sorted(os.path.join(models_dir, f) for f in os.listdir(models_dir)
                             if f.endswith('.yaml') and f != 'paper-reference.yaml')
        self.model_dir_abs = os.path.abspath(models_dir)
        self.env = dict(os.environ)
        self.env['XDG_CACHE_HOME'] = os.path.join(self.out, 'cache')
        self.env.pop('MONOHYDRA_PLUGIN_PATH', None)

    def next_id(self, prefix):
        self.n += 1
        return '%s%05d' % (prefix, self.n)

    # ---- model mutants -------------------------------------------------
    def add_mutant(self, kind, detail, base, data, mode=None):
        cid = self.next_id('m')
        stem = os.path.splitext(os.path.basename(base))[0]
        # Mutants live beside the models' folder layout so that relative
        # plugin_paths keep their meaning: models/ has none, so any folder works.
        path = os.path.join(self.mdir, '%s-%s.yaml' % (cid, stem))
        with open(path, 'wb') as f:
            f.write(data if isinstance(data, bytes) else data.encode('utf-8', 'surrogateescape'))
        if mode is None:
            r = self.rng.random()
            mode = 'short' if r < 0.80 else 'own' if r < 0.90 else 'validate' if r < 0.95 else 'compare'
        csvp = os.path.join(self.wdir, cid + '.csv')
        if mode == 'short':
            argv = ['run', path, '--t-end', str(SHORT_T_END), '--out', csvp]
            c = Case(cid, 'model', kind, detail, argv, csv=csvp, t_end=SHORT_T_END, timeout=30, model=path)
        elif mode == 'own':
            argv = ['run', path, '--out', csvp]
            c = Case(cid, 'model', kind, detail + ' [own dt/t_end]', argv, csv=csvp, timeout=90, model=path)
        elif mode == 'validate':
            argv = ['validate', path]
            c = Case(cid, 'model', kind, detail + ' [validate]', argv, timeout=30, model=path)
        else:
            rep = os.path.join(self.wdir, cid + '-report')
            argv = ['compare', path, '--t-end', str(SHORT_T_END), '--report', rep]
            c = Case(cid, 'model', kind, detail + ' [compare]', argv, report=rep, t_end=SHORT_T_END,
                     timeout=60, model=path)
        self.cases.append(c)

    def sample(self, items, k):
        items = list(items)
        if len(items) <= k:
            return items
        return self.rng.sample(items, k)

    def model_mutants(self):
        texts = {m: open(m, encoding='utf-8').read() for m in self.models}
        caps = self.args.caps
        # 1. delete each key (whole line for block keys, the key: value for flow keys)
        dels = []
        for m, t in texts.items():
            lines = t.split('\n')
            for i, line in enumerate(lines):
                code, _ = split_comment(line)
                for km in KEY_RE.finditer(code):
                    k0 = km.start()
                    before = code[:k0].rstrip()
                    if before == '' or before.endswith('-'):
                        new = lines[:i] + lines[i + 1:]
                        dels.append((m, 'line %d: delete line with key %s' % (i + 1, km.group(1)), '\n'.join(new)))
                    elif before.endswith('{') or before.endswith(','):
                        end = flow_value_end(code, km.end())
                        s0 = k0
                        e0 = end
                        if end < len(code) and code[end] == ',':
                            e0 = end + 1
                            while e0 < len(code) and code[e0] == ' ':
                                e0 += 1
                        elif before.endswith(','):
                            s0 = len(before) - 1
                        newline = line[:s0] + line[e0:]
                        new = lines[:i] + [newline] + lines[i + 1:]
                        dels.append((m, 'line %d: delete flow key %s' % (i + 1, km.group(1)), '\n'.join(new)))
        for m, d, t in self.sample(dels, caps['delete-key']):
            self.add_mutant('delete-key', '%s: %s' % (os.path.basename(m), d), m, t)
        # 2. numbers
        nums = []
        for m, t in texts.items():
            lines = t.split('\n')
            for i, line in enumerate(lines):
                code, com = split_comment(line)
                for nm in NUMBER_RE.finditer(code):
                    for v in NUMBER_VALUES:
                        newline = code[:nm.start()] + v + code[nm.end():] + com
                        nums.append((m, 'line %d: %s -> %s' % (i + 1, nm.group(0), v),
                                     '\n'.join(lines[:i] + [newline] + lines[i + 1:]),
                                     'solver' in code))
        for m, d, t, is_solver in self.sample(nums, caps['number']):
            mode = None
            if is_solver and self.rng.random() < 0.5:
                mode = 'own'
            self.add_mutant('number', '%s: %s' % (os.path.basename(m), d), m, t, mode)
        # 3. names
        name_pats = [
            (r'(parent: )([\w-]+)', ['nosuchbody', 'ground2', '""']),
            (r'(body: )([\w-]+)', ['nosuchbody', '""']),
            (r'(type: )([\w-]+)', ['no-such-type', '""', '42']),
            (r'(formulation: \{name: |formulation: )([\w-]+)', ['no-such-formulation', '""', '[]']),
            (r'(integrator: )([\w-]+)', ['no-such-integrator', '""']),
            (r'(- name: |\{name: )([\w-]+)', ['ground', 'body1', 'dup', '""']),
            (r'(length: |mass: |time: |angle: )([a-z]+)', ['mm', 'g', 'grad']),
            (r'(fixed: \[|free: \[)([\w-]+)', ['nosuch', 'z1', 't']),
            (r'(formulations: \[)([\w-]+)', ['no-such-formulation']),
            (r'(states: \{\w+: |outputs: \{\w+: )([\w-]+)', ['z1', 't', 'KE', 'p1', 'a b']),
            (r'(nodes: \{)(\w+)', ['nosuchnode']),
        ]
        names = []
        for m, t in texts.items():
            lines = t.split('\n')
            for i, line in enumerate(lines):
                code, com = split_comment(line)
                for pat, vals in name_pats:
                    for nm in re.finditer(pat, code):
                        for v in vals:
                            if nm.group(2) == 'ground' and v == 'ground':
                                continue
                            newline = code[:nm.start(2)] + v + code[nm.end(2):] + com
                            names.append((m, 'line %d: %s%s -> %s' % (i + 1, nm.group(1), nm.group(2), v),
                                          '\n'.join(lines[:i] + [newline] + lines[i + 1:])))
        for m, d, t in self.sample(names, caps['name']):
            self.add_mutant('name', '%s: %s' % (os.path.basename(m), d), m, t)
        # 4. truncation at lines and mid-line
        for m, t in texts.items():
            lines = t.split('\n')
            nl = len(lines) - (1 if t.endswith('\n') else 0)  # keep at least one line off
            for k in self.sample(range(1, nl), caps['truncate-line-per-model']):
                self.add_mutant('truncate-line', '%s: first %d lines' % (os.path.basename(m), k), m,
                                '\n'.join(lines[:k]) + '\n')
            positions = [p for p in range(1, len(t)) if t[p - 1] != '\n']
            for p in sorted(self.sample(positions, caps['truncate-mid-per-model'])):
                self.add_mutant('truncate-mid', '%s: first %d bytes (mid-line)' % (os.path.basename(m), p), m, t[:p])
            # a file whose last line break alone is missing
            self.add_mutant('truncate-mid', '%s: without its final line break' % os.path.basename(m), m, t.rstrip('\n'))
        # 5. binary
        for m, t in texts.items():
            b = os.path.basename(m)
            for j in range(caps['binary-per-model']):
                size = self.rng.choice([1, 16, 512, 4096, 70000])
                data = bytes(self.rng.randrange(256) for _ in range(size))
                self.add_mutant('binary', '%s: %d random bytes (#%d)' % (b, size, j), m, data)
            nonul = bytes(self.rng.randrange(1, 256) for _ in range(2048)) + b'\n'
            self.add_mutant('binary', '%s: 2048 random non-NUL bytes' % b, m, nonul)
            half = len(t) // 2
            self.add_mutant('binary', '%s: first half then random bytes' % b, m,
                            t[:half].encode() + bytes(self.rng.randrange(256) for _ in range(300)))
            self.add_mutant('binary', '%s: UTF-16 encoded' % b, m, t.encode('utf-16'))
            self.add_mutant('binary', '%s: invalid UTF-8 in a name' % b, m,
                            t.replace('name: ', 'name: \xff\xfe', 1).encode('latin-1'))
            self.add_mutant('binary', '%s: UTF-8 BOM + CRLF' % b, m, b'\xef\xbb\xbf' + t.replace('\n', '\r\n').encode())
        # 6. empty and near-empty
        base = self.models[0]
        for d, data in [('empty file', ''), ('one line break', '\n'), ('spaces only', '   \n'),
                        ('comment only', '# nothing\n'), ('document marker', '---\n'), ('null', 'null\n'),
                        ('tilde', '~\n'), ('empty list', '[]\n'), ('empty map', '{}\n'), ('string', '"x"\n'),
                        ('number', '42\n'), ('stray comma', ',\n'), ('end marker', '...\n'),
                        ('only units', 'units: {length: m, mass: kg, time: s, angle: deg}\n'),
                        ('units and empty bodies', 'units: {length: m, mass: kg, time: s, angle: deg}\nbodies: []\nsolver: {dt: 0.001, t_end: 1}\n'),
                        ('empty bodies no solver', 'units: {length: m, mass: kg, time: s, angle: deg}\nbodies: []\n')]:
            for mode in ('short', 'own', 'validate'):
                self.add_mutant('empty', d, base, data, mode)
        # 7. circuits
        circ = []
        for m, t in texts.items():
            if 'ports:' not in t:
                continue
            lines = t.split('\n')
            nodes = set()
            for i, line in enumerate(lines):
                code, com = split_comment(line)
                pm = re.search(r'ports: \{([^}]*)\}', code)
                if not pm:
                    continue
                entries = [e.strip() for e in pm.group(1).split(',')]
                for j, e in enumerate(entries):
                    port, node = [x.strip() for x in e.split(':')]
                    nodes.add(node)
                    def rebuild(es):
                        return code[:pm.start(1)] + ', '.join(es) + code[pm.end(1):] + com
                    variants = [
                        ('port %s: node %s -> fresh node' % (port, node), entries[:j] + ['%s: fresh_node_%d' % (port, i)] + entries[j + 1:]),
                        ('drop port %s' % port, entries[:j] + entries[j + 1:]),
                        ('port %s -> unknown port name' % port, entries[:j] + ['nosuchport: %s' % node] + entries[j + 1:]),
                        ('port %s listed twice' % port, entries + [e]),
                        ('port %s: node -> null' % port, entries[:j] + ['%s: null' % port] + entries[j + 1:]),
                    ]
                    for d, es in variants:
                        circ.append((m, 'line %d: %s' % (i + 1, d), '\n'.join(lines[:i] + [rebuild(es)] + lines[i + 1:])))
            sub_i = next(i for i, l in enumerate(lines) if l.startswith('subsystems:'))
            for node in sorted(nodes):
                for d, extra in [
                    ('second pressure source on node %s' % node,
                     '  - {name: dup_source, type: pressure-source, ports: {p: %s}, pressure: 2e6, states: {q: null}}' % node),
                    ('second volume on node %s with another initial pressure' % node,
                     '  - {name: dup_volume, type: volume, ports: {p: %s}, volume: 1e-5, bulk_modulus: 550e6, fluid_bulk_modulus: 1500e6, initial_pressure: 9e6}' % node),
                    ('a throttle from node %s to itself' % node,
                     '  - {name: loop_throttle, type: throttle, ports: {a: %s, b: %s}, area: 1e-5, discharge_coefficient: 0.8, density: 850}' % (node, node)),
                    ('a mechanical spring-damper on hydraulic node %s' % node,
                     '  - {name: bad_domain, type: spring-damper, ports: {p: %s}}' % node),
                ]:
                    circ.append((m, d, '\n'.join(lines[:sub_i + 1] + [extra] + lines[sub_i + 1:])))
            circ.append((m, 'nodes: unknown node', t.replace('nodes: {', 'nodes: {nosuchnode: px, ', 1)))
            circ.append((m, 'nodes: two nodes to one column', re.sub(r'(nodes: \{[^}]*?)(\w+): (\w+), (\w+): (\w+)', r'\1\2: \3, \4: \3', t, count=1)))
            circ.append((m, 'nodes: column named t', re.sub(r'(nodes: \{[^}]*?\w+: )p1', r'\1t', t, count=1)))
            circ.append((m, 'equilibrium: unknown state', t.replace('free: [', 'free: [nosuch, ', 1)))
            circ.append((m, 'equilibrium: every state', re.sub(r'free: \[[^\]]*\]', 'free: [p1, p2, p3, U]', t)))
            circ.append((m, 'equilibrium: empty list', re.sub(r'free: \[[^\]]*\]', 'free: []', t)))
        for m, d, t in self.sample(circ, caps['circuit']):
            self.add_mutant('circuit', '%s: %s' % (os.path.basename(m), d), m, t)
        # 8. structure: wrong types, duplicates, YAML syntax
        struct = []
        for m, t in texts.items():
            b = os.path.basename(m)
            solver_line = [l for l in t.split('\n') if l.startswith('solver:')][0]
            struct += [
                (m, 'bodies: 5', re.sub(r'^bodies:\s*$', 'bodies: 5\nold_bodies:', t, count=1, flags=re.M)),
                (m, 'bodies: {}', re.sub(r'^bodies:\s*$', 'bodies: {}\nold_bodies:', t, count=1, flags=re.M)),
                (m, 'units: a list', re.sub(r'^units: .*$', 'units: [m, kg, s, deg]', t, count=1, flags=re.M)),
                (m, 'gravity: 2 numbers', re.sub(r'^gravity: .*$', 'gravity: [0, -9.81]', t, count=1, flags=re.M)),
                (m, 'gravity: zero', re.sub(r'^gravity: .*$', 'gravity: [0, 0, 0]', t, count=1, flags=re.M)),
                (m, 'solver: a string', t.replace(solver_line, 'solver: fast')),
                (m, 'solver: twice', t + solver_line + '\n'),
                (m, 'unknown top-level key', t + 'nosuchkey: 1\n'),
                (m, 'second document', t + '---\n' + t),
                (m, 'stray comma at the end', t + ',\n'),
                (m, 'tab indentation', t.replace('\n  ', '\n\t', 3)),
                (m, 'unbalanced [', t.replace('[', '[[', 1)),
                (m, 'unbalanced {', t.replace('{', '{{', 1)),
                (m, 'unterminated quote', t.replace('name: ', 'name: "', 1)),
                (m, 'alias to itself', t + 'x: &a [*a]\n'),
                (m, 'anchor/alias billion laughs', t + 'a: &a [1,1,1,1,1,1,1,1,1]\nb: &b [*a,*a,*a,*a,*a,*a,*a,*a,*a]\nc: &c [*b,*b,*b,*b,*b,*b,*b,*b,*b]\nd: &d [*c,*c,*c,*c,*c,*c,*c,*c,*c]\ne: &e [*d,*d,*d,*d,*d,*d,*d,*d,*d]\nf: &f [*e,*e,*e,*e,*e,*e,*e,*e,*e]\n'),
                (m, 'a 1 MB line', t.replace('name: ', 'name: ' + 'x' * 1000000, 1)),
                (m, 'deep nesting 10000', t + 'deep: ' + '[' * 10000 + ']' * 10000 + '\n'),
                (m, 'max_iterations: 1 (run fails mid-way)', t.replace(solver_line, 'solver: {dt: 0.001, t_end: 10, max_iterations: 1}')),
                (m, 'max_iterations: 2.5', t.replace(solver_line, 'solver: {dt: 0.001, t_end: 10, max_iterations: 2.5}')),
                (m, 'max_iterations: 1e12', t.replace(solver_line, 'solver: {dt: 0.001, t_end: 10, max_iterations: 1e12}')),
                (m, 'max_step_halvings: 20, max_iterations: 1', t.replace(solver_line, 'solver: {dt: 0.001, t_end: 10, max_iterations: 1, max_step_halvings: 20}')),
                (m, 'max_step_halvings: 21', t.replace(solver_line, 'solver: {dt: 0.001, t_end: 10, max_step_halvings: 21}')),
                (m, 'tol_position: 1e-300', t.replace(solver_line, 'solver: {dt: 0.001, t_end: 10, tol_position: 1e-300}')),
                (m, 'dt 0.001, t_end 1e5 (1e8 steps, at the limit)', t.replace(solver_line, 'solver: {dt: 0.001, t_end: 1e5}')),
                (m, 'dt = t_end', t.replace(solver_line, 'solver: {dt: 0.5, t_end: 0.5}')),
                (m, 'dt not dividing t_end', t.replace(solver_line, 'solver: {dt: 0.003, t_end: 0.01}')),
                (m, 'duplicate key in solver', t.replace(solver_line, 'solver: {dt: 0.001, dt: 0.002, t_end: 1}')),
                (m, 'z0 huge', t.replace('z0: ', 'z0: 1e18 #', 1)),
                (m, 'zd0 huge', re.sub(r'(mass: [^\n]*\n)', r'\1    zd0: 1e15\n', t, count=1)),
                (m, 'body duplicated', re.sub(r'(\nbodies:\n)((  - [^\n]*\n)(    [^\n]*\n)*)', r'\1\2\2', t, count=1)),
                (m, 'parent cycle', t.replace('parent: ground', 'parent: ' + (re.findall(r'- name: ([\w-]+)', t) or ['x'])[-1], 1)),
                (m, 'plugin_paths: nonexistent', 'plugin_paths: [/nonexistent/plugins]\n' + t),
                (m, 'plugin_paths: a file', 'plugin_paths: [/etc/passwd]\n' + t),
                (m, 'formulation options junk', re.sub(r'^formulation: .*$', 'formulation: {name: penalty, alpha: -1, nosuch: 3}', t, count=1, flags=re.M) if 'formulation:' in t else t + 'formulation: {name: penalty, alpha: -1}\n'),
                (m, 'integrator: mapping without name', t + 'integrator: {rho_inf: 0.5}\n' if 'integrator:' not in t else re.sub(r'^integrator: .*$', 'integrator: {rho_inf: 0.5}', t, count=1, flags=re.M)),
                (m, 'integrator: generalized-alpha rho_inf 2', t + 'integrator: {name: generalized-alpha, rho_inf: 2}\n' if 'integrator:' not in t else re.sub(r'^integrator: .*$', 'integrator: {name: generalized-alpha, rho_inf: 2}', t, count=1, flags=re.M)),
                (m, 'compare: empty list', t + 'compare: {formulations: []}\n' if 'compare:' not in t else re.sub(r'^compare: .*$', 'compare: {formulations: []}', t, count=1, flags=re.M)),
            ]
        for m, d, t in self.sample(struct, caps['structure']):
            mode = 'own' if ('solver' in d or 'max_' in d or 'dt' in d or 'tol' in d) else None
            self.add_mutant('structure', '%s: %s' % (os.path.basename(m), d), m, t, mode)

    # ---- command lines ------------------------------------------------
    def add_cli(self, kind, detail, argv, **kw):
        cid = self.next_id('c')
        kw.setdefault('timeout', 30)
        c = Case(cid, 'cli', kind, detail, argv, **kw)
        self.cases.append(c)
        return c

    def cli_cases(self):
        md = self.model_dir_abs
        fb = os.path.join(md, 'fourbar.yaml')
        dp = os.path.join(md, 'double-pendulum.yaml')
        ff = os.path.join(md, 'fourbar-free.yaml')
        w = self.wdir

        def o(name):
            return os.path.join(w, name)
        runs = [
            ('no arguments at all would run the paper comparison; skipped', None),
            ('unknown command', ['frobnicate']),
            ('run without model', ['run']),
            ('run nonexistent model', ['run', '/nonexistent/model.yaml']),
            ('run a directory', ['run', md]),
            ('run /dev/null', ['run', '/dev/null']),
            ('run /dev/zero', ['run', '/dev/zero']),
            ('run two model files', ['run', dp, fb]),
            ('unknown flag', ['run', dp, '--bogus']),
            ('unknown short flag', ['run', dp, '-x']),
            ('--dt without value', ['run', dp, '--dt']),
            ('--t-end without value', ['run', dp, '--t-end']),
            ('--out without value', ['run', dp, '--t-end', '0.05', '--out']),
            ('--formulation without value', ['run', dp, '--formulation']),
            ('--dt 0', ['run', dp, '--dt', '0']),
            ('--dt -1', ['run', dp, '--dt', '-1']),
            ('--dt nan', ['run', dp, '--dt', 'nan']),
            ('--dt inf', ['run', dp, '--dt', 'inf']),
            ('--dt 1e-320', ['run', dp, '--dt', '1e-320']),
            ('--dt abc', ['run', dp, '--dt', 'abc']),
            ('--dt 0.001x', ['run', dp, '--dt', '0.001x']),
            ('--dt empty', ['run', dp, '--dt', '']),
            ('--dt 0x10', ['run', dp, '--dt', '0x10']),
            ('--t-end inf', ['run', dp, '--t-end', 'inf']),
            ('--t-end 1e19', ['run', dp, '--t-end', '1e19']),
            ('--t-end 0', ['run', dp, '--t-end', '0']),
            ('--t-end -5', ['run', dp, '--t-end', '-5']),
            ('--t-end nan', ['run', dp, '--t-end', 'nan']),
            ('--t-end 5e-324', ['run', dp, '--t-end', '5e-324']),
            ('--dt larger than --t-end', ['run', dp, '--dt', '1', '--t-end', '0.5']),
            ('--dt 0.003 --t-end 0.01 (not a multiple)', ['run', dp, '--dt', '0.003', '--t-end', '0.01', '--out', o('c-nm.csv')]),
            ('--t-end 0.05 twice', ['run', dp, '--t-end', '0.05', '--t-end', '0.1', '--out', o('c-twice.csv')]),
            ('--max-steps 0', ['run', dp, '--max-steps', '0']),
            ('--max-steps -1', ['run', dp, '--max-steps', '-1']),
            ('--max-steps 1e300', ['run', dp, '--t-end', '0.05', '--max-steps', '1e300', '--out', o('c-ms.csv')]),
            ('--max-steps nan', ['run', dp, '--max-steps', 'nan']),
            ('--max-output-bytes 10', ['run', dp, '--t-end', '0.05', '--max-output-bytes', '10', '--out', o('c-mob.csv')]),
            ('--max-output-bytes -1', ['run', dp, '--max-output-bytes', '-1']),
            ('--out /dev/full', ['run', dp, '--t-end', '0.05', '--out', '/dev/full']),
            ('--out /nonexistent/dir/x.csv', ['run', dp, '--t-end', '0.05', '--out', '/nonexistent/dir/x.csv']),
            ('--out a directory', ['run', dp, '--t-end', '0.05', '--out', w]),
            ('--out /proc/version (read-only)', ['run', dp, '--t-end', '0.05', '--out', '/proc/version']),
            ('--out empty string', ['run', dp, '--t-end', '0.05', '--out', '']),
            ('unknown formulation', ['run', dp, '--t-end', '0.05', '--formulation', 'nosuch']),
            ('unknown integrator', ['run', dp, '--t-end', '0.05', '--integrator', 'nosuch']),
            ('formulation open-loop on a closed loop', ['run', ff, '--t-end', '0.05', '--formulation', 'open-loop']),
            ('integrator bdf2', ['run', dp, '--t-end', '0.05', '--integrator', 'bdf2', '--out', o('c-bdf2.csv')]),
            ('formulation penalty on fourbar', ['run', fb, '--t-end', '0.05', '--formulation', 'penalty', '--out', o('c-pen.csv')]),
            ('compare with empty --formulations', ['compare', ff, '--formulations', '', '--t-end', '0.05']),
            ('compare with --formulations ,', ['compare', ff, '--formulations', ',', '--t-end', '0.05']),
            ('compare with duplicates', ['compare', ff, '--formulations', 'penalty,penalty', '--t-end', '0.05', '--report', o('c-cmpdup')]),
            ('compare with duplicate integrators', ['compare', ff, '--formulations', 'penalty', '--integrators', 'trapezoidal,trapezoidal', '--t-end', '0.05', '--report', o('c-cmpdupi')]),
            ('compare with empty --integrators', ['compare', ff, '--integrators', '', '--t-end', '0.05']),
            ('compare with an unknown formulation', ['compare', ff, '--formulations', 'penalty,nosuch', '--t-end', '0.05', '--report', o('c-cmpunk')]),
            ('compare --report /dev/full', ['compare', ff, '--formulations', 'penalty', '--t-end', '0.05', '--report', '/dev/full']),
            ('compare --report /nonexistent/dir', ['compare', ff, '--formulations', 'penalty', '--t-end', '0.05', '--report', '/nonexistent/dir/r']),
            ('compare --t-end 1e19', ['compare', ff, '--t-end', '1e19']),
            ('compare --dt nan', ['compare', ff, '--dt', 'nan']),
            ('compare two models', ['compare', ff, fb, '--t-end', '0.05']),
            ('compare without model', ['compare']),
            ('compare fourbar default lists', ['compare', fb, '--t-end', '0.05', '--report', o('c-cmpfb')]),
            ('validate ok', ['validate', fb]),
            ('validate nonexistent', ['validate', '/nonexistent.yaml']),
            ('validate with --t-end inf', ['validate', fb, '--t-end', 'inf']),
            ('validate two files', ['validate', fb, dp]),
            ('validate without model', ['validate']),
            ('validate --out (not a validate flag)', ['validate', fb, '--out', o('c-v.csv')]),
            ('plugins with junk argument', ['plugins', 'junk']),
            ('plugins with a flag', ['plugins', '--bogus']),
            ('--help', ['--help']),
            ('run --help', ['run', '--help']),
        ]
        for d, argv in runs:
            if argv is None:
                continue
            kw = {}
            if '--out' in argv:
                i = argv.index('--out')
                if i + 1 < len(argv) and argv[i + 1].startswith(w) and argv[i + 1].endswith('.csv'):
                    kw['csv'] = argv[i + 1]
            if '--report' in argv:
                i = argv.index('--report')
                if argv[i + 1].startswith(w):
                    kw['report'] = argv[i + 1]
            if '--t-end' in argv:
                try:
                    kw['t_end'] = float(argv[len(argv) - 1 - argv[::-1].index('--t-end') + 1])
                except (ValueError, IndexError):
                    pass
            self.add_cli('cli', d, argv, **kw)
        # stdout to /dev/full
        for d, argv in [('run, stdout to /dev/full', ['run', dp, '--t-end', '0.05']),
                        ('validate, stdout to /dev/full', ['validate', fb]),
                        ('plugins, stdout to /dev/full', ['plugins']),
                        ('compare, stdout to /dev/full', ['compare', ff, '--formulations', 'penalty', '--t-end', '0.05']),
                        ('--help, stdout to /dev/full', ['--help'])]:
            self.add_cli('cli-stdout-full', d, argv, stdout_file='/dev/full', expect='fail')
        # signals mid-run
        qr = os.path.join(md, 'quickreturn.yaml')
        for sig, name in [(signal.SIGINT, 'SIGINT'), (signal.SIGTERM, 'SIGTERM')]:
            for model, after in [(fb, 1.0), (qr, 2.0), (dp, 0.1)]:
                csvp = o('sig-%s-%s.csv' % (name, os.path.basename(model)))
                self.add_cli('cli-signal', '%s after %.1f s: run %s --t-end 100 --out' % (name, after, os.path.basename(model)),
                             ['run', model, '--t-end', '100', '--out', csvp], csv=csvp, t_end=100.0,
                             sig=sig, sig_after=after, timeout=60)
            csvp = o('sig-%s-dt1e-9.csv' % name)
            self.add_cli('cli-signal', '%s after 3 s: run double-pendulum --dt 1e-9 --t-end 0.05 (5e7 steps) --out' % name,
                         ['run', dp, '--dt', '1e-9', '--t-end', '0.05', '--out', csvp], csv=csvp, t_end=0.05,
                         sig=sig, sig_after=3.0, timeout=60)
            rep = o('sig-%s-compare' % name)
            self.add_cli('cli-signal', '%s after 1.5 s: compare fourbar --t-end 100 --report' % name,
                         ['compare', fb, '--t-end', '100', '--report', rep], report=rep, t_end=100.0,
                         sig=sig, sig_after=1.5, timeout=60)

    # ---- plugins ------------------------------------------------------
    def plugin_cases(self):
        md = self.model_dir_abs
        fb = os.path.join(md, 'fourbar.yaml')
        ff = os.path.join(md, 'fourbar-free.yaml')
        dp = os.path.join(md, 'double-pendulum.yaml')
        faulty = self.args.faulty_dir
        hanging = self.args.hanging_dir
        real_dir = os.path.join(os.path.dirname(os.path.dirname(self.bin)), 'lib', 'monohydra', 'plugins')
        own = os.path.join(self.out, 'own-plugins')
        dirs = []
        if faulty and os.path.isdir(faulty):
            dirs.append(('faulty fixtures (%s)' % ', '.join(sorted(os.listdir(faulty))), faulty))
            if self.args.fixture_dir and os.path.isdir(self.args.fixture_dir):
                dirs.append(('ABI fixtures (%s)' % ', '.join(sorted(os.listdir(self.args.fixture_dir))),
                             self.args.fixture_dir))
        else:
            print('warning: no faulty fixture folder %r: build the mh_faulty_* targets' % faulty, file=sys.stderr)
        # libraries made here, one per folder so that each verdict is visible
        real = sorted(f for f in os.listdir(real_dir) if f.endswith('.so')) if os.path.isdir(real_dir) else []
        src = os.path.join(real_dir, 'monohydra-hydraulics.so') if 'monohydra-hydraulics.so' in real else (
            os.path.join(real_dir, real[0]) if real else None)
        made = []

        def mk(name, data=None, mode=None, symlink=None, directory=False):
            d = os.path.join(own, name.replace('.so', '').replace('/', '_'))
            os.makedirs(d, exist_ok=True)
            p = os.path.join(d, name)
            if directory:
                os.makedirs(p, exist_ok=True)
            elif symlink is not None:
                if os.path.lexists(p):
                    os.remove(p)
                os.symlink(symlink, p)
            else:
                with open(p, 'wb') as f:
                    f.write(data)
                if mode is not None:
                    os.chmod(p, mode)
            made.append((name, d))
        mk('empty.so', b'')
        mk('random.so', bytes(self.rng.randrange(256) for _ in range(8192)))
        mk('elfheader-only.so', b'\x7fELF\x02\x01\x01' + b'\0' * 57)
        mk('text.so', b'this is not a library\n')
        mk('unreadable.so', b'\x7fELF', mode=0)
        mk('loop.so', symlink='loop.so')
        mk('dir.so', directory=True)
        if src:
            blob = open(src, 'rb').read()
            for frac in (0.01, 0.1, 0.25, 0.5, 0.75, 0.9, 0.99):
                mk('cut%02d.so' % int(frac * 100), blob[:int(len(blob) * frac)])
            flip = bytearray(blob)
            for _ in range(64):
                flip[self.rng.randrange(64, len(flip))] ^= 0xff
            mk('bitflips.so', bytes(flip))
            mk('duplicate-hydraulics.so', blob)
        for lib in ('/lib/x86_64-linux-gnu/libm.so.6', '/usr/lib/x86_64-linux-gnu/libm.so.6'):
            if os.path.exists(lib):
                mk('libm-copy.so', open(lib, 'rb').read())
                break
        for name, d in made:
            dirs.append((name, d))
        all_dir = os.path.join(own, 'all')
        os.makedirs(all_dir, exist_ok=True)
        for name, d in made:
            p = os.path.join(d, name)
            q = os.path.join(all_dir, name)
            if not os.path.lexists(q):
                if os.path.islink(p):
                    os.symlink(os.readlink(p), q)
                elif os.path.isdir(p):
                    os.makedirs(q, exist_ok=True)
                else:
                    shutil.copy2(p, q)
                    if name == 'unreadable.so':
                        os.chmod(q, 0)
        dirs.append(('all own faulty libraries together', all_dir))
        for d, path in dirs:
            for cache in ('on', 'off'):
                env = dict(self.env)
                env['MONOHYDRA_PLUGIN_PATH'] = path
                if cache == 'off':
                    env['MONOHYDRA_PROBE_CACHE'] = 'off'
                tag = '%s, cache %s' % (d, cache)
                self.add_cli('plugin', 'plugins with %s' % tag, ['plugins'], env=env)
                if cache == 'off':
                    continue
                c = self.next_id('p')
                csvp = os.path.join(self.wdir, c + '.csv')
                self.add_cli('plugin', 'run fourbar --t-end 0.05 with %s' % tag,
                             ['run', fb, '--t-end', '0.05', '--out', csvp], env=env, csv=csvp, t_end=0.05)
        if faulty and os.path.isdir(faulty):
            env = dict(self.env)
            env['MONOHYDRA_PLUGIN_PATH'] = faulty
            for t_end in ('0.05', '0.5'):
                csvp = os.path.join(self.wdir, 'crashing-run-%s.csv' % t_end)
                self.add_cli('plugin', 'run fourbar-free --formulation crashing-formulation --t-end %s' % t_end,
                             ['run', ff, '--formulation', 'crashing-formulation', '--t-end', t_end, '--out', csvp],
                             env=env, csv=csvp, t_end=float(t_end))
                rep = os.path.join(self.wdir, 'crashing-compare-%s' % t_end)
                self.add_cli('plugin', 'compare fourbar-free crashing-formulation,penalty --t-end %s' % t_end,
                             ['compare', ff, '--formulations', 'crashing-formulation,penalty', '--t-end', t_end,
                              '--report', rep], env=env, report=rep, t_end=float(t_end), timeout=60)
            self.add_cli('plugin', 'validate fourbar-free --formulation crashing-formulation',
                         ['validate', ff, '--formulation', 'crashing-formulation'], env=env)
            self.add_cli('plugin', 'run double-pendulum --formulation crashing-formulation --t-end 0.5 --integrator bdf2',
                         ['run', dp, '--formulation', 'crashing-formulation', '--integrator', 'bdf2', '--t-end', '0.5',
                          '--out', os.path.join(self.wdir, 'crashing-dp.csv')], env=env,
                         csv=os.path.join(self.wdir, 'crashing-dp.csv'), t_end=0.5)
            # a model naming the faulty folder in plugin_paths
            t = open(ff, encoding='utf-8').read()
            p = os.path.join(self.mdir, 'plugin_paths-faulty.yaml')
            with open(p, 'w') as f:
                f.write('plugin_paths: [%s]\n' % faulty + t.replace('formulation: {name: double-step}', 'formulation: crashing-formulation'))
            csvp = os.path.join(self.wdir, 'plugin_paths-faulty.csv')
            self.add_cli('plugin', 'model with plugin_paths: [faulty], formulation crashing-formulation, --t-end 0.5',
                         ['run', p, '--t-end', '0.5', '--out', csvp], csv=csvp, t_end=0.5)
        if hanging and os.path.isdir(hanging):
            env = dict(self.env)
            env['MONOHYDRA_PLUGIN_PATH'] = hanging
            env['MONOHYDRA_PROBE_CACHE'] = 'off'
            self.add_cli('plugin', 'plugins with hang_in_init (probe limit 10 s)', ['plugins'], env=env, timeout=40)
            csvp = os.path.join(self.wdir, 'hanging.csv')
            self.add_cli('plugin', 'run double-pendulum with hang_in_init', ['run', dp, '--t-end', '0.05', '--out', csvp],
                         env=env, csv=csvp, t_end=0.05, timeout=40)
        for d, val in [('nonexistent folder', '/nonexistent/plugins'), ('a file', '/etc/passwd'),
                       ('empty string', ''), ('colons only', ':::'), ('relative junk', 'no/such:../x'),
                       ('very long path', '/x' * 5000)]:
            env = dict(self.env)
            env['MONOHYDRA_PLUGIN_PATH'] = val
            self.add_cli('plugin-path', 'plugins with MONOHYDRA_PLUGIN_PATH = %s' % d, ['plugins'], env=env)
            csvp = os.path.join(self.wdir, 'pp-%d.csv' % len(self.cases))
            self.add_cli('plugin-path', 'run fourbar with MONOHYDRA_PLUGIN_PATH = %s' % d,
                         ['run', fb, '--t-end', '0.05', '--out', csvp], env=env, csv=csvp, t_end=0.05)
        env = dict(self.env)
        env['MONOHYDRA_PROBE_CACHE'] = '/nonexistent/dir/cache'
        self.add_cli('plugin-path', 'plugins with MONOHYDRA_PROBE_CACHE in a missing folder', ['plugins'], env=env)
        fifo = os.path.join(self.out, 'cache', 'fifo')
        os.mkfifo(fifo)
        # NEVER name the device itself: the cache is saved by writing FILE.pid.tmp and renaming it
        # over FILE, which (as root) replaces /dev/null or /dev/zero by a regular file.  A symlink
        # to the device reads the same, and the rename replaces only the link.
        devs = []
        for dev in ('/dev/full', '/dev/zero', '/dev/null'):
            link = os.path.join(self.out, 'cache', 'link-to-' + os.path.basename(dev))
            os.symlink(dev, link)
            devs.append(('a symlink to ' + dev, link))
        for d, val in devs + [('a FIFO', fifo), ('a directory', self.wdir)]:
            env = dict(self.env)
            env['MONOHYDRA_PROBE_CACHE'] = val
            self.add_cli('plugin-path', 'plugins with MONOHYDRA_PROBE_CACHE = %s' % d, ['plugins'], env=env)
            csvp = os.path.join(self.wdir, 'pc-%d.csv' % len(self.cases))
            self.add_cli('plugin-path', 'run double-pendulum with MONOHYDRA_PROBE_CACHE = %s' % d,
                         ['run', dp, '--t-end', '0.05', '--out', csvp], env=env, csv=csvp, t_end=0.05)


def csv_facts(path):
    """(data rows, last line whole?, exists)"""
    if not path or not os.path.isfile(path):
        return None
    with open(path, 'rb') as f:
        data = f.read()
    if not data:
        return (0, True, 0)
    lines = data.split(b'\n')
    whole = data.endswith(b'\n')
    if whole:
        lines = lines[:-1]
    ncols = lines[0].count(b',')
    bad = [i for i, l in enumerate(lines) if l.count(b',') != ncols]
    return (len(lines) - 1, whole and not bad, len(lines))


def run_case(args, b, c):
    env = c.env if c.env is not None else b.env
    stdout = open(c.stdout_file, 'wb') if c.stdout_file else subprocess.PIPE
    t0 = time.monotonic()
    r0 = os.times()
    p = subprocess.Popen([b.bin] + c.argv, stdout=stdout, stderr=subprocess.PIPE, env=env,
                         start_new_session=True, stdin=subprocess.DEVNULL)
    hung = False
    sent = None
    try:
        if c.sig is not None:
            try:
                p.wait(timeout=c.sig_after)
            except subprocess.TimeoutExpired:
                os.kill(p.pid, c.sig)
                sent = c.sig
        out, err = p.communicate(timeout=c.timeout)
    except subprocess.TimeoutExpired:
        hung = True
        os.killpg(p.pid, signal.SIGKILL)
        out, err = p.communicate()
    if c.stdout_file:
        stdout.close()
    wall = time.monotonic() - t0
    out = (out or b'').decode('utf-8', 'replace')
    err = (err or b'').decode('utf-8', 'replace')
    rc = p.returncode
    cls, why = classify(c, rc, out, err, hung, sent)
    return dict(rc=rc, out=out, err=err, wall=wall, cls=cls, why=why, sent=sent)


def names_something(c, err):
    if FILE_LINE_RE.search(err):
        return 'file:line'
    if c.model and c.model in err:
        return 'file'
    if re.search(r"subsystem '[^']+'", err):
        return 'component'
    if re.search(r'--[a-z-]+', err):
        return 'flag'
    if '.so' in err or 'plugin' in err:
        return 'plugin'
    if 'standard output' in err:
        return 'output'
    for a in c.argv[1:]:
        for v in a.split(','):
            if len(v) > 1 and v in err:
                return 'value'
    if 'command line' in err or 'usage' in err.lower():
        return 'usage'
    return None


def classify(c, rc, out, err, hung, sent):
    fa = csv_facts(c.csv)
    rows = '' if not fa else '; CSV: %d rows%s' % (fa[0], '' if fa[1] else ', last line cut')
    if hung:
        return 'hang', 'killed after %s s%s' % (c.timeout, rows)
    if 'internal error' in err:
        return 'crash', 'internal error'
    expected_sig_rc = {signal.SIGINT: 130, signal.SIGTERM: 143}
    if rc < 0:
        if sent is not None and -rc == sent:
            return 'crash', 'died of our %s instead of exiting %d%s' % (signal.Signals(sent).name, expected_sig_rc[sent], rows)
        return 'crash', 'killed by %s%s' % (signal.Signals(-rc).name, rows)
    if rc == 70:
        return 'crash', 'exit 70'
    if rc >= 128 and (sent is None or rc != expected_sig_rc[sent]):
        return 'crash', 'exit %d' % rc
    # rows
    s = SUMMARY_RE.search(out)
    done = asked = None
    if s:
        done, asked = int(s.group(1)), int(s.group(2))
        dt, t_end = float(s.group(3)), float(s.group(4))
    facts = csv_facts(c.csv)
    csvs = []
    if c.csv:
        csvs.append((c.csv, facts))
    if c.report and os.path.isdir(c.report):
        for f in sorted(os.listdir(c.report)):
            if f.endswith('.csv'):
                p = os.path.join(c.report, f)
                csvs.append((p, csv_facts(p)))
    for p, fa in csvs:
        if fa and fa[2] > 0 and not fa[1]:
            return 'lost-rows', '%s: last line cut or a row with another column count' % os.path.basename(p)
    if facts and s and facts[2] > 0 and facts[0] < done + 1:
        return 'lost-rows', 'summary says %d steps done but the CSV has %d rows' % (done, facts[0])
    m = STEP_MSG_RE.search(err)
    if m and c.csv and int(m.group(1)) > 1:
        k = int(m.group(1))
        if not facts or facts[0] < k:
            return 'lost-rows', 'failed at step %d but the CSV has %s rows' % (k, facts[0] if facts else 'no')
    m = STOP_MSG_RE.search(err)
    if m and c.csv and c.csv in err and 'every row' in err:
        k = int(m.group(1))
        if not facts or facts[0] < k + 1:
            return 'lost-rows', 'stopped at step %d but the CSV has %s rows' % (k, facts[0] if facts else 'no')
    if sent is not None:
        if rc == expected_sig_rc[sent]:
            if c.csv and not facts:
                return 'lost-rows', 'interrupted: no CSV'
            return 'ok', 'exit %d after %s, %s rows' % (rc, signal.Signals(sent).name, facts[0] if facts else '-')
        if rc == 0:
            pass  # finished before the signal: checked as a normal run below
        else:
            return 'other', 'exit %d after %s' % (rc, signal.Signals(sent).name)
    if rc == 0:
        if c.expect == 'fail':
            return 'short-exit0', 'exit 0 although its output could not be written'
        if c.argv[0] == 'run':
            if not s:
                return 'short-exit0', 'exit 0 without a steps summary'
            if done != asked:
                return 'short-exit0', 'exit 0 with %d of %d steps' % (done, asked)
            if asked != round(t_end / dt):
                return 'short-exit0', 'asked %d steps but t_end/dt = %g' % (asked, t_end / dt)
            if c.t_end is not None and abs(t_end - c.t_end) > 1e-12 * max(1, c.t_end):
                return 'short-exit0', 'ran to t_end = %g, asked %g' % (t_end, c.t_end)
            if c.csv and (not facts or facts[0] != asked + 1):
                return 'short-exit0', 'CSV has %s rows, expected %d' % (facts[0] if facts else 'no', asked + 1)
            return 'ok', '%d steps' % done
        if c.argv[0] == 'compare':
            h = re.search(r'dt = ([^ ]+) s, t = 0 \.\. ([^ ]+) s', out)
            if c.report:
                if not h:
                    return 'short-exit0', 'exit 0 without the compare header'
                want = round(float(h.group(2)) / float(h.group(1))) + 1
                got = [(os.path.basename(p), fa[0] if fa else None) for p, fa in csvs]
                if not got:
                    return 'short-exit0', 'exit 0 but no CSV in the report'
                short = [g for g in got if g[1] != want]
                if short:
                    return 'short-exit0', 'CSV rows %s, expected %d' % (short, want)
                if 'FAILED' in out or 'crashed' in out:
                    return 'short-exit0', 'exit 0 with a failed run in the table'
            return 'ok', 'compare'
        return 'ok', 'exit 0'
    if rc in (1, 2):
        if not err.strip():
            return 'refused-vague', 'exit %d without a message' % rc
        what = names_something(c, err)
        if s and done is not None and done < asked and rc == 1:
            return 'refused', 'run failed after %d of %d steps, rows kept' % (done, asked)
        if what:
            return 'refused', 'exit %d, names the %s' % (rc, what)
        return 'refused-vague', 'exit %d: %s' % (rc, err.strip().splitlines()[-1][:120])
    return 'other', 'exit %d' % rc


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--bin', required=True)
    ap.add_argument('--out', required=True)
    ap.add_argument('--seed', type=int, default=20261130)
    ap.add_argument('--models', default=os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'models'))
    ap.add_argument('--faulty-dir', default=None, help='default: BIN/../../tests/faulty-plugins')
    ap.add_argument('--hanging-dir', default=None, help='default: BIN/../../tests/hanging-plugin')
    ap.add_argument('--fixture-dir', default=None, help='default: BIN/../../tests/fixtures')
    ap.add_argument('--jobs', type=int, default=2)
    ap.add_argument('--only', default=None, help='comma list of groups: model,cli,plugin')
    ap.add_argument('--scale', type=float, default=1.0, help='multiply the model-mutant caps')
    args = ap.parse_args()
    bdir = os.path.dirname(os.path.dirname(os.path.abspath(args.bin)))
    args.faulty_dir = args.faulty_dir or os.path.join(bdir, 'tests', 'faulty-plugins')
    args.fixture_dir = args.fixture_dir or os.path.join(bdir, 'tests', 'fixtures')
    args.hanging_dir = args.hanging_dir or os.path.join(bdir, 'tests', 'hanging-plugin')
    caps = {'delete-key': 380, 'number': 760, 'name': 170, 'truncate-line-per-model': 10,
            'truncate-mid-per-model': 8, 'binary-per-model': 3, 'circuit': 90, 'structure': 200}
    args.caps = {k: max(1, int(v * args.scale)) for k, v in caps.items()}
    if os.path.exists(args.out):
        shutil.rmtree(args.out)
    for d in ('mutants', 'work', 'cache'):
        os.makedirs(os.path.join(args.out, d))
    b = Builder(args)
    groups = set((args.only or 'model,cli,plugin').split(','))
    if 'model' in groups:
        b.model_mutants()
    if 'cli' in groups:
        b.cli_cases()
    if 'plugin' in groups:
        b.plugin_cases()
    cases = b.cases
    print('%d cases (seed %d), %d jobs' % (len(cases), args.seed, args.jobs), file=sys.stderr)
    t0 = time.monotonic()
    ct0 = os.times()
    done = 0
    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as ex:
        futs = {ex.submit(run_case, args, b, c): c for c in cases}
        for f in concurrent.futures.as_completed(futs):
            c = futs[f]
            c.result = f.result()
            done += 1
            if done % 200 == 0:
                print('  %d/%d (%.0f s)' % (done, len(cases), time.monotonic() - t0), file=sys.stderr)
    wall = time.monotonic() - t0
    ct1 = os.times()
    cpu = (ct1.children_user - ct0.children_user) + (ct1.children_system - ct0.children_system)
    classes = ['crash', 'hang', 'short-exit0', 'lost-rows', 'refused', 'refused-vague', 'ok', 'other']
    with open(os.path.join(args.out, 'cases.csv'), 'w', newline='') as f:
        wr = csv.writer(f)
        wr.writerow(['id', 'group', 'kind', 'class', 'why', 'exit', 'wall_s', 'detail', 'command', 'stderr_last_line'])
        for c in cases:
            r = c.result
            last = r['err'].strip().splitlines()[-1] if r['err'].strip() else ''
            wr.writerow([c.cid, c.group, c.kind, r['cls'], r['why'], r['rc'], '%.3f' % r['wall'], c.detail,
                         ' '.join(['monohydra'] + c.argv) + (' > ' + c.stdout_file if c.stdout_file else ''), last[:400]])
            if r['cls'] not in ('ok', 'refused'):
                with open(os.path.join(args.out, 'work', c.cid + '.log'), 'w') as g:
                    g.write('argv: %r\nexit: %s\nwhy: %s\n--- stdout\n%s\n--- stderr\n%s\n' % (
                        c.argv, r['rc'], r['why'], r['out'][-4000:], r['err'][-4000:]))
            elif c.csv and os.path.isfile(c.csv):
                os.remove(c.csv)
    kinds = sorted(set(c.kind for c in cases), key=lambda k: [x.kind for x in cases].index(k))
    table = collections.Counter((c.kind, c.result['cls']) for c in cases)
    lines = []
    hdr = '%-18s %6s ' % ('kind', 'cases') + ' '.join('%8s' % k[:8] for k in classes)
    lines.append(hdr)
    lines.append('-' * len(hdr))
    for k in kinds + ['TOTAL']:
        row = [table[(k, cl)] if k != 'TOTAL' else sum(table[(kk, cl)] for kk in kinds) for cl in classes]
        lines.append('%-18s %6d ' % (k, sum(row)) + ' '.join('%8d' % x for x in row))
    tot = collections.Counter(c.result['cls'] for c in cases)
    lines.append('')
    lines.append('crashes: %d, hangs: %d, exit-0 runs that did less than asked: %d, lost rows: %d' % (
        tot['crash'], tot['hang'], tot['short-exit0'], tot['lost-rows']))
    lines.append('wall %.0f s, CPU of the monohydra processes %.0f s, seed %d' % (wall, cpu, args.seed))
    bad = [c for c in cases if c.result['cls'] not in ('ok', 'refused')]
    if bad:
        lines.append('')
        lines.append('cases to look at:')
        for c in bad:
            lines.append('  %s %-13s %-14s %s | %s' % (c.cid, c.result['cls'], c.kind, c.detail, c.result['why']))
    text = '\n'.join(lines) + '\n'
    with open(os.path.join(args.out, 'summary.txt'), 'w') as f:
        f.write(text)
    print(text)
    return 0


if __name__ == '__main__':
    sys.exit(main())
