#!/usr/bin/env python3
"""Generate the tables of the audit suites from the public headers.

    gen_invalid.py OUT.c [LIST.txt]

Reads every IGEA_API prototype of include/igea/*.h and the comment above
it, takes each function's valid baseline call from baselines.py (or derives
it from the parameter names and types), and writes OUT.c: per function a
set-up, a call wrapper and the list of invalid mutations of the baseline
(every pointer NULL unless the header allows it, every size 0, -1 and
INT_MIN, every leading dimension one too small, every enumeration out of
range, NaN and +-Inf in every double scalar and in the first element of
every double array). LIST.txt, if given, lists what was generated.

Standard library only. Exits 1, naming the function and parameter, when a
baseline cannot be resolved, so a new exported function fails the build
until its baseline is known.
"""
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
import baselines  # noqa: E402

# Classes of int scalar parameters by name (baselines.py's _int overrides).
INT_CLASS = {}
for _n in ('m n N k nsamp nsens ntau nk nterms nepochs nflights ngroup ncomp nblock ny nz q '
           'nrows ntau_max nwin max_iter p').split():
    INT_CLASS[_n] = 'size'
for _n in ('layout model method rule kind noise system output variant policy sigma_inc fdi '
           'iterative weighted track term').split():
    INT_CLASS[_n] = 'enum'
for _n in 'seed flight row0 first_flight nthreads n_test'.split():
    INT_CLASS[_n] = 'nonneg'
INT_CLASS['fault_sensor'] = 'index'
# Classes of the first element of const int arrays: code (an index or an
# enumeration: -1 and 12345 invalid), count (-1 invalid), flag (0 or 1: -1
# and 2 invalid), free (any value).
INTARR_CLASS = {'terms': 'code', 'axes': 'code', 'type': 'code', 'first': 'code',
                'member': 'code', 'dof': 'count', 'n_reject': 'count', 'x_fixed': 'flag',
                'keep': 'free', 'unit_id': 'free', 'k': 'free'}


class Param:
    def __init__(self, ctype, name):
        self.ctype = ' '.join(ctype.split())
        self.name = name
        t = self.ctype.replace(' ', '')
        self.const = t.startswith('const')
        base = t[5:] if self.const else t
        # a const char * (a name) is held in an int buffer filled by its
        # baseline's set: code; its only mutation is NULL
        self.at = {'int': 'AT_INT', 'double': 'AT_DBL', 'double*': 'AT_PD', 'int*': 'AT_PI',
                   'igea_rls*': 'AT_H', 'igea_rls**': 'AT_HO',
                   'igea_sim_model*': 'AT_H', 'igea_sim_model**': 'AT_HO',
                   'igea_io_reader*': 'AT_H', 'igea_io_reader**': 'AT_HO',
                   'igea_whiten*': 'AT_H', 'igea_whiten**': 'AT_HO',
                   'igea_stability_stream*': 'AT_H', 'igea_stability_stream**': 'AT_HO',
                   'char*': 'AT_PI' if self.const else None}.get(base)
        # the handle's kind (audit.h AUDIT_HK_*)
        self.hkind = ('AUDIT_HK_SIM' if base.startswith('igea_sim_model') else
                      'AUDIT_HK_IO' if base.startswith('igea_io_reader') else
                      'AUDIT_HK_WHITEN' if base.startswith('igea_whiten') else
                      'AUDIT_HK_STREAM' if base.startswith('igea_stability_stream') else
                      'AUDIT_HK_RLS')
        if self.at is None:
            raise SystemExit('gen_invalid: unsupported parameter type %r (%s)' % (ctype, name))
        self.isptr = self.at not in ('AT_INT', 'AT_DBL')


class Func:
    def __init__(self, ret, name, params, comment, header):
        self.ret, self.name, self.params = ret, name, params
        self.comment, self.header = comment, header


def parse_headers():
    funcs = []
    for fn in sorted(os.listdir(os.path.join(ROOT, 'include', 'igea'))):
        if not fn.endswith('.h'):
            continue
        text = open(os.path.join(ROOT, 'include', 'igea', fn)).read()
        # comments that start a line (not the trailing comments of #defines)
        comments = [(m.start(), m.end(), m.group(1)) for m in
                    re.finditer(r'(?m)^[ \t]*/\*(.*?)\*/', text, re.S)]
        for m in re.finditer(r'IGEA_API\s+([^;{]*?)\b(igea_\w+)\s*\(([^)]*)\)\s*;', text, re.S):
            ret = ' '.join(m.group(1).split())
            params = []
            plist = ' '.join(m.group(3).split())
            if plist != 'void':
                for p in plist.split(','):
                    pm = re.match(r'\s*(.*?)\b(\w+)\s*$', p)
                    params.append(Param(pm.group(1), pm.group(2)))
            before = [c for c in comments if c[1] <= m.start()]
            comment = before[-1][2] if before else ''
            funcs.append(Func(ret, m.group(2), params, comment, fn))
    return funcs


def optional_from_comment(func):
    """Pointer parameters the comment says may be NULL: "NULL" between a
    mention of the parameter and the next parameter named as an item
    ("12 name", "name:", "name[", "name (")."""
    text = ' '.join(func.comment.replace('*', ' ').split())
    text = re.sub(r'(set to |Non-|non-)NULL', '', text)
    names = [p.name for p in func.params]
    opt = set()
    for p in func.params:
        if not p.isptr:
            continue
        for m in re.finditer(r'(?<![\w.])%s(?![\w(])' % re.escape(p.name), text):
            rest = text[m.end():m.end() + 200]
            cut = len(rest)
            for other in names:
                if other == p.name:
                    continue
                om = re.search(r'(\b\d+ %s\b|(?<![\w.])%s(?=:|\[| \(|,? \d))'
                               % (re.escape(other), re.escape(other)), rest)
                if om and om.start() < cut:
                    cut = om.start()
            if 'NULL' in rest[:cut]:
                opt.add(p.name)
    return opt


def fill_code(p, val, idx):
    """C statements that create and fill the buffer of pointer p."""
    if p.at == 'AT_H':
        new = {'h': 'audit_rls_new(3, 2, 2)', 'h0': 'audit_rls_new(3, 2, 0)',
               'hpoly': 'audit_rls_new_ex(3, 2, 2, IGEA_RLS_POLYNOMIAL, 3, IGEA_RLS_ANOMALY_NONE)',
               'hiso': 'audit_rls_new_ex(3, 2, 2, IGEA_RLS_STANDARD, 1, IGEA_RLS_ANOMALY_ISOLATE)',
               'm': 'audit_sim_model_new(0)', 'mtraj': 'audit_sim_model_new(1)',
               'mnl': 'audit_sim_model_new(2)',
               'io0': 'audit_io_new(0)', 'io': 'audit_io_new(1)', 'io2': 'audit_io_new(2)',
               'iol': 'audit_io_new(3)', 'w': 'audit_whiten_new()',
               'wx': 'audit_whiten_xcov_new()',
               'st': 'audit_stream_new()', 'st0': 'audit_stream_new0()'}
        kinds = {'m': 'AUDIT_HK_SIM', 'mtraj': 'AUDIT_HK_SIM', 'mnl': 'AUDIT_HK_SIM',
                 'io0': 'AUDIT_HK_IO', 'io': 'AUDIT_HK_IO', 'io2': 'AUDIT_HK_IO',
                 'iol': 'AUDIT_HK_IO', 'w': 'AUDIT_HK_WHITEN', 'wx': 'AUDIT_HK_WHITEN',
                 'st': 'AUDIT_HK_STREAM', 'st0': 'AUDIT_HK_STREAM'}
        if kinds.get(val, 'AUDIT_HK_RLS') != p.hkind:
            raise SystemExit('gen_invalid: handle %s: %s is not of its type' % (p.name, val))
        if val not in new:
            raise SystemExit('gen_invalid: handle %s needs one of %s' % (p.name, ', '.join(new)))
        return ('    c->hkind[%d] = %s;\n' % (idx, p.hkind) +
                '    c->type[%d] = AT_H; c->isconst[%d] = %d; c->buf[%d] = %s;\n'
                '    if (!c->buf[%d]) { fprintf(stderr, "audit: handle set-up failed\\n"); exit(2); }\n'
                '    c->pv[%d] = c->buf[%d];\n' % (idx, idx, int(p.const), idx, new[val], idx, idx,
                                                 idx))
    if p.at == 'AT_HO':
        return ('    c->hkind[%d] = %s;\n' % (idx, p.hkind) +
                '    c->type[%d] = AT_HO; c->buf[%d] = malloc(sizeof(igea_rls *));\n'
                '    if (!c->buf[%d]) exit(2);\n'
                '    *(igea_rls **)c->buf[%d] = AUDIT_BAD_HANDLE; c->pv[%d] = c->buf[%d];\n'
                % (idx, idx, idx, idx, idx, idx))
    ct = 'double' if p.at == 'AT_PD' else 'int'
    if val == 'NULL':
        return '    c->type[%d] = %s; c->isconst[%d] = %d; c->pv[%d] = NULL;\n' % (
            idx, p.at, idx, int(p.const), idx)
    s = '    {\n        %s *b_ = audit_buf(c, %d, %s, %d, sizeof(%s));\n' % (
        ct, idx, p.at, int(p.const), ct)
    if val == 'out':
        s += '        (void)b_;\n'
    elif val.startswith('set:'):
        s += '        ' + val[4:] + '\n'
    elif val.startswith('['):
        items = [x.strip() for x in val.strip('[]').split(',')]
        s += '        for (long i = 0; i < AUDIT_NB; i++) b_[i] = 0;\n'
        for i, x in enumerate(items):
            s += '        b_[%d] = %s;\n' % (i, x)
    else:
        expr = {'u': 'au(i)', 'pos': 'apos(i)', '0': '0'}.get(val)
        if expr is None:
            if not val.startswith('c:'):
                raise SystemExit('gen_invalid: %s: bad value %r' % (p.name, val))
            expr = val[2:]
        s += '        for (long i = 0; i < AUDIT_NB; i++) b_[i] = (%s)(%s);\n' % (ct, expr)
    s += '    }\n'
    return s


def is_fill(v):
    """Whether a NAME_DEFAULTS value is for a pointer (else a scalar)."""
    return v in ('u', 'pos', '0', 'h', 'NULL', 'out') or v.startswith(('c:', '[', 'set:'))


def resolve(func):
    """The baseline value of every parameter; exits when one is missing."""
    entry = func.entry
    vals = {}
    for p in func.params:
        if p.name in entry:
            v = entry[p.name]
        elif p.at in ('AT_H', 'AT_HO'):
            v = ({'AUDIT_HK_SIM': 'm', 'AUDIT_HK_IO': 'io', 'AUDIT_HK_WHITEN': 'w',
                  'AUDIT_HK_STREAM': 'st'}.get(p.hkind, 'h')
                 if p.at == 'AT_H' else 'ho')
        elif p.isptr and not p.const:
            v = 'out'
        elif p.name in baselines.NAME_DEFAULTS and p.isptr == is_fill(
                baselines.NAME_DEFAULTS[p.name]):
            v = baselines.NAME_DEFAULTS[p.name]
        else:
            raise SystemExit('gen_invalid: no baseline value for parameter %s of %s (%s): add it '
                             'to tests/audit/baselines.py' % (p.name, func.name, func.header))
        vals[p.name] = str(v)
    return vals


def dq(s):
    return '"' + s.replace('\\', '\\\\').replace('"', '\\"') + '"'


def generate(funcs):
    out = ['/* Generated by tests/audit/gen_invalid.py from include/igea/ *.h and\n'
           ' * tests/audit/baselines.py. Do not edit. */\n', '#include "audit.h"\n\n']
    listing = []
    table = []
    total_fail = 0
    for f in funcs:
        entry = f.entry
        vals = resolve(f)
        names = [p.name for p in f.params]
        opt = optional_from_comment(f)
        opt |= set(entry.get('_opt', []))
        opt -= set(entry.get('_req', []))
        null_any = set(entry.get('_null_any', []))
        zero_ok = set(entry.get('_zero_ok', []))
        inf_ok = entry.get('_inf_ok', [])
        nan_ok = set(entry.get('_nan_ok', []))
        intcls = dict(entry.get('_int', {}))
        ignored = set(entry.get('_ignored', []))
        if len(f.params) > 24:
            raise SystemExit('gen_invalid: %s has more than AUDIT_MAXARG parameters' % f.name)
        # set-up
        s = ['static void setup_%s(audit_call *c)\n{\n    memset(c, 0, sizeof *c);\n'
             '    c->nargs = %d;\n' % (f.cid, len(f.params))]
        scal = [p for p in f.params if not p.isptr]
        done, order = set(), []
        while len(order) < len(scal):
            moved = False
            for p in scal:
                if p.name in done:
                    continue
                refs = set(re.findall(r'\b[A-Za-z_]\w*\b', vals[p.name])) & set(names)
                refs.discard(p.name)
                if refs <= done:
                    order.append(p)
                    done.add(p.name)
                    moved = True
            if not moved:
                raise SystemExit('gen_invalid: circular baseline values in %s' % f.name)
        for p in order:
            ct = 'int' if p.at == 'AT_INT' else 'double'
            s.append('    %s %s = %s;\n' % (ct, p.name, vals[p.name]))
        for i, p in enumerate(f.params):
            if p.at == 'AT_INT':
                s.append('    c->type[%d] = AT_INT; c->iv[%d] = %s;\n' % (i, i, p.name))
            elif p.at == 'AT_DBL':
                s.append('    c->type[%d] = AT_DBL; c->dv[%d] = %s;\n' % (i, i, p.name))
        for i, p in enumerate(f.params):
            if p.isptr:
                s.append(fill_code(p, vals[p.name], i))
        s.append('}\n\n')
        out += s
        # call wrapper
        args = []
        for i, p in enumerate(f.params):
            if p.at == 'AT_INT':
                args.append('(int)c->iv[%d]' % i)
            elif p.at == 'AT_DBL':
                args.append('c->dv[%d]' % i)
            else:
                args.append('(%s)c->pv[%d]' % (p.ctype, i))
        callexpr = '%s(%s)' % (f.name, ', '.join(args))
        consumes = -1
        if f.ret == 'void':
            hs = [i for i, p in enumerate(f.params) if p.at == 'AT_H']
            body = '    %s;\n' % callexpr
            if f.name.endswith('_free') and hs:
                consumes = hs[0]
                body += '    if (c->pv[%d]) c->consumed[%d] = 1;\n' % (hs[0], hs[0])
            body += '    return 0;\n'
        elif f.ret == 'const char *':
            body = '    return %s != NULL ? 0 : -1;\n' % callexpr
        elif f.ret == 'const double *':  # a view: NULL is a valid answer
            body = '    (void)%s;\n    return 0;\n' % callexpr
        elif entry.get('_ret') == 'bool':
            body = '    int r = %s;\n    return r == 1 ? 0 : r == 0 ? -1 : -2;\n' % callexpr
        elif f.ret == 'int':
            body = '    return %s;\n' % callexpr
        else:
            raise SystemExit('gen_invalid: unsupported return type %r of %s' % (f.ret, f.name))
        if not f.params:
            body = '    (void)c;\n' + body
        out.append('static int call_%s(audit_call *c)\n{\n%s}\n\n' % (f.cid, body))
        # mutations
        muts = []

        def add(i, kind, ival, dval, expect, label):
            muts.append((i, kind, ival, dval, expect, label))

        def infexp(name, sign):
            for x in inf_ok:
                if x == name or x == name + sign:
                    return 'EX_ANY'
            return 'EX_FAIL'
        cls_list = []
        for i, p in enumerate(f.params):
            v = vals[p.name]
            if p.at == 'AT_INT':
                cls = intcls.get(p.name) or ('ld' if p.name.startswith('ld') else
                                              INT_CLASS.get(p.name))
                if cls is None:
                    raise SystemExit('gen_invalid: int parameter %s of %s has no class: add it '
                                     'to INT_CLASS or to _int in baselines.py' % (p.name, f.name))
                cls_list.append('%s:%s' % (p.name, cls))
                if entry.get('_ret') == 'bool':
                    if cls == 'enum':
                        add(i, 'MK_INT', '12345', '0', 'EX_FAIL', '%s=12345' % p.name)
                        add(i, 'MK_INT', '-12345', '0', 'EX_FAIL', '%s=-12345' % p.name)
                    continue
                if cls == 'size':
                    add(i, 'MK_INT', '0', '0', 'EX_OK' if p.name in zero_ok else 'EX_FAIL',
                        '%s=0' % p.name)
                    add(i, 'MK_INT', '-1', '0', 'EX_FAIL', '%s=-1' % p.name)
                    add(i, 'MK_INT', 'INT_MIN', '0', 'EX_FAIL', '%s=INT_MIN' % p.name)
                elif cls == 'ld':
                    add(i, 'MK_IADD', '-1', '0', 'EX_FAIL',
                        '%s=%s-1' % (p.name, v.replace(' ', '')))
                elif cls == 'enum':
                    add(i, 'MK_INT', '12345', '0', 'EX_FAIL', '%s=12345' % p.name)
                    add(i, 'MK_INT', '-12345', '0', 'EX_FAIL', '%s=-12345' % p.name)
                elif cls == 'nonneg':
                    add(i, 'MK_INT', '-1', '0', 'EX_FAIL', '%s=-1' % p.name)
                    add(i, 'MK_INT', 'INT_MIN', '0', 'EX_FAIL', '%s=INT_MIN' % p.name)
                elif cls == 'index':
                    add(i, 'MK_INT', '-2', '0', 'EX_FAIL', '%s=-2' % p.name)
                    add(i, 'MK_INT', '12345', '0', 'EX_FAIL', '%s=12345' % p.name)
                elif cls != 'free':
                    raise SystemExit('gen_invalid: unknown class %s' % cls)
            elif p.at == 'AT_DBL':
                add(i, 'MK_DBL', '0', 'NAN', 'EX_ANY' if p.name in nan_ok else 'EX_FAIL',
                    '%s=NaN' % p.name)
                add(i, 'MK_DBL', '0', 'INFINITY', infexp(p.name, '+'), '%s=+Inf' % p.name)
                add(i, 'MK_DBL', '0', '-INFINITY', infexp(p.name, '-'), '%s=-Inf' % p.name)
            else:
                if v == 'NULL':
                    continue
                if p.name in null_any:
                    exp = 'EX_ANY'
                elif p.name in opt or (p.at == 'AT_H' and f.name.endswith('_free')):
                    exp = 'EX_OK'
                else:
                    exp = 'EX_FAIL'
                add(i, 'MK_NULL', '0', '0', exp, '%s=NULL' % p.name)
                if p.at == 'AT_PD' and v != 'out':
                    add(i, 'MK_ELEM', '0', 'NAN', 'EX_ANY' if p.name in nan_ok else 'EX_FAIL',
                        '%s[0]=NaN' % p.name)
                    add(i, 'MK_ELEM', '0', 'INFINITY', infexp(p.name, '+'), '%s[0]=+Inf' % p.name)
                    add(i, 'MK_ELEM', '0', '-INFINITY', infexp(p.name, '-'),
                        '%s[0]=-Inf' % p.name)
                for idx in entry.get('_neg_bad', {}).get(p.name, []):
                    add(i, 'MK_ELEM', str(idx), '-1.0', 'EX_FAIL', '%s[%d]=-1' % (p.name, idx))
                if p.at == 'AT_PI' and p.const:
                    acls = entry.get('_intarr', {}).get(p.name) or INTARR_CLASS.get(p.name)
                    if acls is None:
                        raise SystemExit('gen_invalid: int array %s of %s has no class: add it '
                                         'to INTARR_CLASS or to _intarr in baselines.py'
                                         % (p.name, f.name))
                    bad = {'code': ['-1', '12345'], 'count': ['-1'], 'flag': ['-1', '2'],
                           'free': []}[acls]
                    for x in bad:
                        add(i, 'MK_IELEM', x, '0', 'EX_FAIL', '%s[0]=%s' % (p.name, x))
        valid = set(entry.get('_valid', []))
        muts = [(m[0], m[1], m[2], m[3], 'EX_OK' if m[5] in valid else
                 'EX_ANY' if names[m[0]] in ignored else m[4], m[5]) for m in muts]
        unknown = valid - {m[5] for m in muts}
        if unknown:
            raise SystemExit('gen_invalid: _valid of %s names no mutation: %s'
                             % (f.label, ', '.join(sorted(unknown))))
        for (pname, cval, exp) in entry.get('_extra', []):
            i = names.index(pname)
            kind = 'MK_INT' if f.params[i].at == 'AT_INT' else 'MK_DBL'
            add(i, kind, cval if kind == 'MK_INT' else '0', cval if kind == 'MK_DBL' else '0',
                {'ok': 'EX_OK', 'fail': 'EX_FAIL', 'any': 'EX_ANY'}[exp],
                '%s=%s' % (pname, cval))
        if entry.get('_expect') == 'any':
            muts = []  # extreme data: the baseline itself is the check
        out.append('static const audit_mut muts_%s[] = {\n' % f.cid)
        for (i, kind, ival, dval, exp, label) in muts:
            out.append('    {%d, %s, %s, %s, %s, %s},\n' % (i, kind, ival, dval, exp, dq(label)))
        if not muts:
            out.append('    {0, MK_INT, 0, 0, EX_ANY, NULL},\n')
        out.append('};\n')
        out.append('static const char *const names_%s[] = {%s};\n\n' % (
            f.cid, ', '.join(dq(n) for n in names) if names else 'NULL'))
        nan_out = 0
        for pname in entry.get('_nan_out', []):
            nan_out |= 1 << names.index(pname)
        base_any = int(entry.get('_expect') == 'any')
        progress = 0
        for pname in entry.get('_progress', []):
            progress |= 1 << names.index(pname)
        table.append('    {"%s", %d, names_%s, setup_%s, call_%s, muts_%s, %d, %d, %d, %#xul, %d, '
                     '%#xul},\n'
                     % (f.label, len(f.params), f.cid, f.cid, f.cid, f.cid, len(muts),
                        0 if entry.get('_threads') is False else 1, consumes, nan_out, base_any,
                        progress))
        total_fail += sum(1 for m in muts if m[4] == 'EX_FAIL')
        listing.append('%s (%s): %d mutations; may be NULL: %s; ints: %s' % (
            f.label, f.header, len(muts), ', '.join(sorted(opt & set(names))) or '-',
            ', '.join(cls_list) or '-'))
    out.append('static const audit_fn audit_fns[] = {\n%s};\n' % ''.join(table))
    out.append('static const int audit_nfns = %d;\n' % len(funcs))
    return ''.join(out), listing, total_fail


def main():
    if len(sys.argv) < 2:
        raise SystemExit(__doc__)
    funcs = parse_headers()
    names = {f.name for f in funcs}
    stale = sorted(set(baselines.BASE) - names)
    if stale:
        raise SystemExit('gen_invalid: baselines.py names functions that are not exported: %s'
                         % ', '.join(stale))
    stale = sorted(set(getattr(baselines, 'VARIANTS', {})) - names)
    if stale:
        raise SystemExit('gen_invalid: VARIANTS names functions that are not exported: %s'
                         % ', '.join(stale))
    calls = []
    for f in funcs:
        f.label, f.cid, f.entry = f.name, f.name, baselines.BASE.get(f.name, {})
        calls.append(f)
        for vname, over in sorted(getattr(baselines, 'VARIANTS', {}).get(f.name, {}).items()):
            v = Func(f.ret, f.name, f.params, f.comment, f.header)
            v.label, v.cid = f.name + '@' + vname, f.name + '__' + vname
            v.entry = dict(f.entry)
            v.entry.update(over)
            calls.append(v)
    code, listing, nfail = generate(calls)
    tmp = sys.argv[1] + '.tmp'
    with open(tmp, 'w') as fh:
        fh.write(code)
    os.replace(tmp, sys.argv[1])
    if len(sys.argv) > 2:
        with open(sys.argv[2], 'w') as fh:
            fh.write('\n'.join(listing) + '\n')
    print('gen_invalid: %d exported functions, %d baselines, %d invalid-argument mutations'
          % (len(funcs), len(calls), nfail))


if __name__ == '__main__':
    main()
