#!/usr/bin/env python3
"""Write igea.f90, the Fortran module of the C API, from the public
headers include/igea/*.h, with the parser of gen_capi.py (the one that
writes the Python mirror), so the two cannot drift apart.

    gen_fortran.py OUT.f90

The module `igea` (Fortran 2003 iso_c_binding, plus the OPTIONAL dummy
arguments of interoperable procedures of TS 29113 / Fortran 2018) holds:

  - an interface for every IGEA_API function, with the header's argument
    names: int and double scalars by value; pointers by reference, as
    assumed-size arrays x(*) (a Fortran array is passed as it is: the
    library is column-major), or as scalars for the pointers listed in
    SCALARS below; every pointer argument is OPTIONAL, an absent one is
    passed as NULL (the library refuses NULL where its header does not
    allow it, with status -i); const char * arguments are
    character(kind=c_char) arrays (terminate them with c_null_char); a
    const char * or const double * result and a handle (igea_rls *,
    igea_sim_model *) are type(c_ptr) (c_f_pointer makes an array of the
    latter); void functions are subroutines;
  - a named parameter for every #define IGEA_X of the headers with its C
    value (a constant whose name is, case aside, a function's gets
    the suffix _CONST: IGEA_VERSION_NUMBER_CONST);
  - for every slot of an array whose length is a macro P_LEN or P_COLS
    (options, info, counts, table columns), IGEAF_<slot> = IGEA_<slot> + 1,
    the 1-based Fortran index: opts(IGEAF_EQERR_OPT_ALPHA).

The module has no code of its own: a program links -ligea only.
Standard library only.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import gen_capi  # noqa: E402

# Pointer arguments that point at one value (the header says so in words);
# every other pointer is an array. A new function's scalar output that is
# not listed here is an array of one element for Fortran callers.
SCALARS = {
    "igea_accel_merge": "npos", "igea_accel_hysteresis": "npos", "igea_accel_analyze": "rank",
    "igea_accel_criterion": "logdet rank",
    "igea_choice_code": "code",
    "igea_envfun_default_spec": "spec", "igea_envfun_default_terms": "n",
    "igea_normal_qr_accumulate": "rows",
    "igea_redund_exponential": "R mtbf", "igea_redund_reliability_series": "out",
    "igea_redund_reliability_parallel": "out", "igea_redund_reliability_kofn": "out",
    "igea_redund_fdi": "isolated", "igea_redund_skew_check": "faulty_d",
    "igea_redund_fuse": "value fused_sigma", "igea_redund_false_alarm": "p",
    "igea_redund_window_count": "nwin", "igea_redund_monitor_intervals": "niv",
    "igea_regress_ls": "rank sigma2", "igea_regress_ebr": "lam rank sigma2",
    "igea_regress_ridge": "k_used sigma2", "igea_regress_pce": "nused sigma2",
    "igea_regress_collinearity": "rank",
    "igea_rls_run": "n_done", "igea_rls_get_size": "m k",
    "igea_sim_trajectory_length": "nsamp", "igea_sim_model_get_size": "m N",
    "igea_stability_octave_taus": "ntau",
    "igea_stability_fit_boot": "chi2",
    "igea_stats_normal_cdf": "p", "igea_stats_erfinv": "x", "igea_stats_normal_quantile": "z",
    "igea_stats_chi2_cdf": "p", "igea_stats_chi2_sf": "q", "igea_stats_chi2_quantile": "x",
    "igea_stats_chi2_upper": "x", "igea_stats_union_size": "size",
    "igea_stats_verdict_thresholds": "a b size",
    "igea_redund_window_length": "samples seconds",
    "igea_impact_point": "tf", "igea_impact_circle_prob": "prob", "igea_impact_cep": "radius",
    "igea_impact_cep_approx": "radius", "igea_impact_circle_prob_offset": "prob",
    "igea_impact_cep_offset": "radius", "igea_triad_static": "nint",
    "igea_io_reader_next": "nread", "igea_io_parse_number": "x",
    "igea_io_reader_view": "nread",
    "igea_dw_summary": "max_abs",
    # one value each in their header comments, found missing by
    # tests/python/test_fortran_scalars.py
    "igea_dw_compute": "bad", "igea_dw_compute_k": "bad", "igea_envfun_all_terms": "n",
    "igea_whiten_get_state": "epochs group", "igea_whiten_accumulate": "bad_epoch",
    "igea_whiten_accumulate_xcov": "bad_epoch",
    "igea_regress_ls_ex": "sigma2", "igea_regress_ridge_ex": "k_used sigma2",
    "igea_regress_ls_full": "sigma2",
    "igea_regress_pce_ex": "nused sigma2", "igea_rls_get_q": "q",
    "igea_stability_taus": "ntau", "igea_stability_fit": "chi2",
    "igea_stats_normal_sf": "q", "igea_stats_t_sf": "q", "igea_stats_t_quantile": "t",
    "igea_stats_f_sf": "q",
    "igea_stability_stream_samples": "n", "igea_stability_stream_result": "ntau",
}

_KIND = {"int": "integer(c_int)", "double": "real(c_double)"}


def fortran_arg(fname, ctype, name):
    """(declaration, imported kind names) of one dummy argument."""
    const = "const" in ctype.split() or ctype.startswith("const")
    t = ctype.replace("const", "").replace(" ", "")
    if t in _KIND:
        return "%s, value :: %s" % (_KIND[t], name), {"c_int" if t == "int" else "c_double"}
    if t in ("int*", "double*"):
        kind = _KIND[t[:-1]]
        scalar = name in SCALARS.get(fname, "").split()
        intent = ", intent(in)" if const else ""
        return ("%s%s, optional :: %s%s" % (kind, intent, name, "" if scalar else "(*)"),
                {"c_int" if t == "int*" else "c_double"})
    if t == "char*":
        return ("character(kind=c_char), intent(in), optional :: %s(*)" % name, {"c_char"})
    if gen_capi._HANDLE.match(t):
        return "type(c_ptr), value :: %s" % name, {"c_ptr"}
    if gen_capi._HANDLE_OUT.match(t):
        return "type(c_ptr), intent(out) :: %s" % name, {"c_ptr"}
    raise SystemExit("gen_fortran: %s: unsupported C type %r of %s" % (fname, ctype, name))


def _lines(head, items, tail, indent, width=100):
    """head item, item, ... tail with & continuations, lines <= width."""
    out, line = [], head
    for i, it in enumerate(items):
        piece = it + (", " if i < len(items) - 1 else "")
        if len(line) + len(piece.rstrip()) + 2 > width:
            out.append(line.rstrip() + " &")
            line = " " * indent
        line += piece
    if len(line) + len(tail) + 2 > width:
        out.append(line.rstrip() + " &")
        line = " " * indent
    out.append(line + tail)
    return "\n".join(out) + "\n"


def _distinct(params):
    """Fortran names are case-insensitive: an argument whose name equals an
    earlier one but for case (nav_gravity's g and G) gets the suffix _2."""
    seen, out = set(), []
    for pt, pn in params:
        fn = pn + "_2" if pn.lower() in seen else pn
        seen.add(fn.lower())
        out.append((pt, fn))
    return out


def interface(fn, ret, name, params):
    where = "%s: %s" % (fn, name)
    params = _distinct(params)
    decls, kinds = [], set()
    for pt, pn in params:
        d, k = fortran_arg(name, pt, pn)
        decls.append(d)
        kinds |= k
    r = ret.replace("const", "").replace(" ", "")
    if r == "void":
        kw, res = "subroutine", None
    elif r == "int":
        kw, res = "function", "integer(c_int) :: igea_result"
        kinds.add("c_int")
    elif r == "double":
        kw, res = "function", "real(c_double) :: igea_result"
        kinds.add("c_double")
    elif r in ("char*", "double*"):
        kw, res = "function", "type(c_ptr) :: igea_result"
        kinds.add("c_ptr")
    else:
        raise SystemExit("gen_fortran: %s: unsupported return type %r" % (where, ret))
    tail = ") bind(c, name='%s')%s" % (name, " result(igea_result)" if res else "")
    s = _lines("    %s %s(" % (kw, name), [pn for _, pn in params], tail, 8)
    s += "      import :: %s\n" % ", ".join(sorted(kinds)) if kinds else ""
    s += "      implicit none\n"
    for d in decls:
        s += "      %s\n" % d
    if res:
        s += "      %s\n" % res
    s += "    end %s %s\n" % (kw, name)
    return s


def _fvalue(v):
    if isinstance(v, bool) or not isinstance(v, (int, float, str)):
        raise SystemExit("gen_fortran: unsupported constant value %r" % (v,))
    if isinstance(v, str):
        return "character(len=*), parameter", "'%s'" % v.replace("'", "''")
    if isinstance(v, int):
        if not -2**31 < v < 2**31:
            raise SystemExit("gen_fortran: integer constant %d beyond c_int" % v)
        return "integer(c_int), parameter", ("(%d)" % v) if v < 0 else "%d" % v
    r = repr(float(v))
    if r in ("inf", "-inf", "nan"):
        raise SystemExit("gen_fortran: constant %r has no Fortran literal" % v)
    mant, _, exp = r.partition("e")
    if "." not in mant:
        mant += ".0"
    return "real(c_double), parameter", "%sd%s" % (mant, exp or "0")


def slot_arrays(names):
    """{slot macro: its array's length macro} for the P_x whose longest
    prefix P has a P_LEN or P_COLS macro."""
    lens = {n.rsplit("_", 1)[0] for n in names if n.endswith(("_LEN", "_COLS"))}
    out = {}
    for n in names:
        if n.endswith(("_LEN", "_COLS")):
            continue
        parts = n.split("_")
        for k in range(len(parts) - 1, 1, -1):
            p = "_".join(parts[:k])
            if p in lens:
                out[n] = p
                break
    return out


def generate(include=gen_capi.INCLUDE):
    macros, funcs = gen_capi.parse(include)
    values = gen_capi.evaluate(macros)
    fnames = {f[2] for f in funcs}
    names = [n for _, n, _ in macros]
    slots = slot_arrays(names)
    out = ["! The Fortran module of libigea: generated by python/gen_fortran.py from\n"
           "! include/igea/*.h. Do not edit: 'make' regenerates it after a header changes.\n"
           "!\n"
           "! use igea  gives an interface for every function of the C API, with its\n"
           "! header's argument names (the header comments are the documentation), and\n"
           "! a parameter for every IGEA_* constant, with its C value. C arrays are\n"
           "! 0-based: for every slot of an options, info or counts array (or a table\n"
           "! column), IGEAF_<slot> = IGEA_<slot> + 1 is its 1-based Fortran index,\n"
           "! e.g. opts(IGEAF_EQERR_OPT_ALPHA), info(IGEAF_STATS_INFO_CHI2).\n"
           "! Scalars are passed by value; pointers by reference (arrays as they are:\n"
           "! the library is column-major); every pointer argument is OPTIONAL and an\n"
           "! absent one is NULL (refused with status -i where the header does not\n"
           "! allow NULL). Strings in: terminate with c_null_char; strings out and\n"
           "! handles: type(c_ptr) (igea_c_strlen gives a result string's length).\n"
           "! A constant named, case aside, like a function has the suffix _CONST.\n"
           "! Build: gfortran $(pkg-config --variable=fflags igea) prog.f90\n"
           "!        $(pkg-config --libs igea)\n"
           "module igea\n"
           "  use, intrinsic :: iso_c_binding\n"
           "  implicit none\n"
           "  public\n"]
    header = None
    for fn, name, _ in macros:
        if fn != header:
            header = fn
            out.append("\n  ! igea/%s\n" % fn)
        decl, lit = _fvalue(values[name])
        fname = name + "_CONST" if name.lower() in fnames else name
        out.append("  %s :: %s = %s\n" % (decl, fname, lit))
        if name in slots and isinstance(values[name], int):
            out.append("  integer(c_int), parameter :: IGEAF_%s = %d  ! 1-based index into [%s_%s]\n"
                       % (name[5:], values[name] + 1, slots[name],
                          "COLS" if slots[name] + "_COLS" in names else "LEN"))
    out.append("\n  interface\n")
    header = None
    for fn, ret, name, params in funcs:
        if fn != header:
            header = fn
            out.append("\n    ! igea/%s\n" % fn)
        out.append(interface(fn, ret, name, params))
    out.append("\n    ! the C library's strlen, for the const char * results above\n"
               "    function igea_c_strlen(s) bind(c, name='strlen') result(igea_result)\n"
               "      import :: c_ptr, c_size_t\n"
               "      implicit none\n"
               "      type(c_ptr), value :: s\n"
               "      integer(c_size_t) :: igea_result\n"
               "    end function igea_c_strlen\n")
    out.append("  end interface\nend module igea\n")
    return "".join(out)


def main(argv):
    if len(argv) != 1:
        sys.stderr.write("usage: gen_fortran.py OUT.f90\n")
        return 2
    text = generate()
    tmp = argv[0] + ".tmp%d" % os.getpid()
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, argv[0])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
