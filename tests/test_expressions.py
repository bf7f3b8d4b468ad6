"""Safe expression evaluator (screwkit.pm._expressions) and path input (screwkit.paths)."""

from __future__ import annotations

import argparse
import ast
import inspect
import time

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from screwkit.errors import InputError, ScrewkitError
from screwkit.paths import (add_path_arguments, parse_assignment, path_from_args, path_from_csv,
                            path_from_expressions)
from screwkit.pm import _expressions as expressions, evaluate, parse_expression

T = np.linspace(0.0, 1.0, 11)


# ----------------------------------------------------------------------------- values

@pytest.mark.parametrize("text, reference", [
    ("10*sin(2*pi*t)", lambda t: 10 * np.sin(2 * np.pi * t)),
    ("70+30*t", lambda t: 70 + 30 * t),
    ("5*cos(pi*t)**2 - 3", lambda t: 5 * np.cos(np.pi * t) ** 2 - 3),
    ("-t**2", lambda t: -(t ** 2)),
    ("2**3**t", lambda t: 2.0 ** (3.0 ** t)),
    ("(1 + t) / (2 - t)", lambda t: (1 + t) / (2 - t)),
    ("+t - -t", lambda t: 2 * t),
    ("atan2(t - 0.5, 0.25)", lambda t: np.arctan2(t - 0.5, 0.25)),
    ("asin(t) + acos(t) + atan(t)", lambda t: np.arcsin(t) + np.arccos(t) + np.arctan(t)),
    ("tan(t) + sqrt(t) + exp(-t) + log(1 + t)",
     lambda t: np.tan(t) + np.sqrt(t) + np.exp(-t) + np.log1p(t)),
    ("abs(t - 0.5)", lambda t: np.abs(t - 0.5)),
    ("min(t, 0.3, 1 - t)", lambda t: np.minimum(np.minimum(t, 0.3), 1 - t)),
    ("max(t, 0.5)", lambda t: np.maximum(t, 0.5)),
    ("e**t", lambda t: np.exp(t)),
    ("1e-3 * t + .5", lambda t: 0.001 * t + 0.5),
])
def test_values_match_numpy(text, reference):
    np.testing.assert_allclose(evaluate(text, T), reference(T), rtol=1e-14, atol=1e-14)


def test_constant_expression_is_broadcast_to_t():
    out = evaluate("80", T)
    assert out.shape == T.shape and np.all(out == 80.0)


def test_integer_literals_are_floats():
    # Python ints would make 3/2 fine but 2**-1 or huge powers exact; floats throughout
    np.testing.assert_allclose(evaluate("2**-1 + 3/2 + 0*t", T), 2.0)


@settings(max_examples=40, deadline=None)
@given(a=st.floats(-1e3, 1e3), b=st.floats(-1e3, 1e3), c=st.floats(0.1, 10))
def test_random_affine_trig_against_numpy(a, b, c):
    text = f"{a!r}*t + {b!r}*cos({c!r}*t)"
    np.testing.assert_allclose(evaluate(text, T), a * T + b * np.cos(c * T),
                               rtol=1e-12, atol=1e-9)


def test_other_variable_names():
    e = parse_expression("x*y + 1", variables=("x", "y"))
    np.testing.assert_allclose(e(x=np.array([1.0, 2.0]), y=3.0), [4.0, 7.0])
    with pytest.raises(InputError, match="no value given for y"):
        e(x=1.0)


# ----------------------------------------------------------------------------- rejection

@pytest.mark.parametrize("text, token, column", [
    ("__import__('os')", "'__import__'", 1),
    ("__import__('os').system('true')", ".system", 17),
    ("t.__class__", ".__class__", 2),
    ("(1).__class__.__bases__", ".__bases__", 14),
    ("(lambda: 1)()", "lambda", 2),
    ("x + 1", "'x'", 1),
    ("sin(t) + y", "'y'", 10),
    ("np.sin(t)", ".sin", 3),
    ("exec('1')", "'exec'", 1),
    ("eval('t')", "'eval'", 1),
    ("globals()", "'globals'", 1),
    ("t[0]", "subscript", 1),
    ("t % 2", "'%'", 3),
    ("t // 2", "'//'", 3),
    ("t if t else 1", "conditional", 1),
    ("t > 1", "comparison", 1),
    ("[t]", "list", 1),
    ("'abc'", "'abc'", 1),
    ("1j * t", "1j", 1),
    ("True + t", "True", 1),
    ("sin(x=t)", "x=t", 5),
    ("sin(t, t)", "'sin'", 1),
    ("atan2(t)", "'atan2'", 1),
    ("max(t)", "'max'", 1),
    ("sin", "'sin'", 1),
    ("~t", "'~'", 1),
    ("[c for c in ()]", "comprehension", 1),
    ("(y := 2)", ":=", 2),
])
def test_rejected_with_token_and_column(text, token, column):
    with pytest.raises(InputError) as info:
        evaluate(text, T)
    msg = str(info.value)
    assert token in msg, msg
    assert f"(column {column})" in msg, msg
    assert isinstance(info.value, ScrewkitError)


@pytest.mark.parametrize("text, near, column", [
    ("2 +* 3", "'*'", 4),
    ("import os", "'import'", 1),
    ("t; 1", "';'", 2),
    ("t +", "at the end", 4),
    ("sin(t", "'('", 4),
])
def test_syntax_errors_name_position(text, near, column):
    with pytest.raises(InputError) as info:
        evaluate(text, T)
    msg = str(info.value)
    assert "syntax error" in msg and near in msg and f"(column {column})" in msg, msg


def test_leading_spaces_keep_columns_of_the_original_text():
    with pytest.raises(InputError, match=r"'y' .*\(column 7\)"):
        evaluate("  t + y", T)


def test_huge_powers_do_not_hang_and_are_reported():
    start = time.perf_counter()
    with pytest.raises(InputError, match="infinite"):
        evaluate("9**9**9**9", T)
    assert time.perf_counter() - start < 1.0


def test_deep_nesting_and_length_are_input_errors():
    with pytest.raises(InputError):
        evaluate("(" * 300 + "t" + ")" * 300, T)
    with pytest.raises(InputError, match="too long"):
        evaluate("t+" * 2000 + "t", T)
    with pytest.raises(InputError, match="empty"):
        evaluate("   ", T)
    with pytest.raises(InputError, match="line breaks"):
        evaluate("t\n+1", T)


def test_non_finite_results_name_the_sample():
    with pytest.raises(InputError, match=r"infinite at t = 0 \(sample 0\)"):
        evaluate("log(t)", T)
    with pytest.raises(InputError, match=r"NaN at t = 0\.6 \(sample 6\)"):
        evaluate("sqrt(0.55 - t)", T)
    out = parse_expression("log(t)")(T, check_finite=False)
    assert out[0] == -np.inf and np.isfinite(out[1:]).all()


def test_module_never_calls_eval_exec_or_compile():
    tree = ast.parse(inspect.getsource(expressions))
    called = {n.func.id for n in ast.walk(tree)
              if isinstance(n, ast.Call) and isinstance(n.func, ast.Name)}
    assert not called & {"eval", "exec", "compile", "__import__"}


# ----------------------------------------------------------------------------- paths: CSV

INDEP = ("alpha", "beta", "Zo")


def _csv(tmp_path, text, name="path.csv"):
    p = tmp_path / name
    p.write_text(text)
    return p


def test_csv_reads_angles_in_degrees_into_radians(tmp_path):
    p = _csv(tmp_path, "t,alpha,beta,Zo\n# a comment\n\n0,10,-5,70\n0.5,20,0,85\n1,30,5,100\n")
    path = path_from_csv(p, INDEP)
    np.testing.assert_array_equal(path.t, [0.0, 0.5, 1.0])
    np.testing.assert_allclose(path.values["alpha"], np.array([10, 20, 30]) * np.pi / 180)
    np.testing.assert_allclose(path.values["beta"], np.array([-5, 0, 5]) * np.pi / 180)
    np.testing.assert_array_equal(path.values["Zo"], [70.0, 85.0, 100.0])
    np.testing.assert_allclose(path.display()["alpha"], [10, 20, 30])
    assert path.names == ("Zo", "alpha", "beta") and len(path) == 3
    assert path.sample(1) == pytest.approx({"alpha": np.pi / 9, "beta": 0.0, "Zo": 85.0})


def test_csv_columns_in_any_order_and_radians(tmp_path):
    p = _csv(tmp_path, "Zo,beta,t,alpha\n70,0.1,0,0.2\n")
    path = path_from_csv(p, INDEP, angle_unit="rad")
    assert path.values["alpha"][0] == 0.2 and path.values["Zo"][0] == 70.0


@pytest.mark.parametrize("content, pieces", [
    ("t,alpha,beta\n0,1,2\n", ["missing Zo", "line 1"]),
    ("t,alpha,beta,Zo,foo\n0,1,2,3,4\n", ["'foo' is unknown"]),
    ("t,alpha,beta,Zo,alpah\n0,1,2,3,4\n", ["'alpah' is unknown", "did you mean 'alpha'"]),
    ("t,alpha,beta,Zo,Xo\n0,1,2,3,4\n", ["'Xo' is not independent"]),
    ("alpha,beta,Zo\n1,2,3\n", ["no column 't'"]),
    ("t,alpha,alpha,beta,Zo\n0,1,1,2,3\n", ["'alpha' appears twice"]),
    ("t,alpha,beta,Zo\n0,1,2,70\n\n# c\n0.5,2,nan,80\n", ["line 5", "column 'beta'", "'nan' is not a finite number"]),
    ("t,alpha,beta,Zo\n0,1,2,70\n0.5,2,x,80\n", ["line 3", "column 'beta'", "'x' is not a number"]),
    ("t,alpha,beta,Zo\n0,1,,70\n", ["line 2", "column 'beta'", "empty cell"]),
    ("t,alpha,beta,Zo\n0,1,2,inf\n", ["line 2", "column 'Zo'", "'inf' is not a finite number"]),
    ("t,alpha,beta,Zo\n0,1,2\n", ["line 2", "3 cells", "header has 4"]),
    ("t,alpha,beta,Zo\n0,1,2,70\n0,2,3,80\n", ["line 3", "increase strictly"]),
    ("t,alpha,beta,Zo\n", ["no data rows"]),
    ("", ["empty file"]),
])
def test_csv_errors_name_line_and_column(tmp_path, content, pieces):
    p = _csv(tmp_path, content)
    with pytest.raises(InputError) as info:
        path_from_csv(p, INDEP)
    msg = str(info.value)
    assert str(p) in msg or "line" not in " ".join(pieces)
    for piece in pieces:
        assert piece in msg, msg


def test_csv_unreadable_file(tmp_path):
    with pytest.raises(InputError, match="cannot read path file"):
        path_from_csv(tmp_path / "nope.csv", INDEP)


# ----------------------------------------------------------------------------- paths: expressions

def test_expressions_are_sampled_over_the_t_range():
    path = path_from_expressions(["alpha=10*sin(2*pi*t)", "beta = 0", "Zo=70+30*t"], INDEP,
                                 samples=5, t_range=(0.0, 2.0))
    t = np.linspace(0.0, 2.0, 5)
    np.testing.assert_array_equal(path.t, t)
    np.testing.assert_allclose(path.values["alpha"], np.radians(10 * np.sin(2 * np.pi * t)),
                               atol=1e-15)
    np.testing.assert_allclose(path.values["Zo"], 70 + 30 * t)
    assert path.values["beta"].shape == (5,)


def test_expressions_as_mapping():
    path = path_from_expressions({"alpha": "t", "beta": "2*t", "Zo": "80"}, INDEP, samples=3)
    np.testing.assert_allclose(path.display()["beta"], [0.0, 1.0, 2.0])


@pytest.mark.parametrize("exprs, kwargs, piece", [
    (["alpha=t", "Zo=1"], {}, "missing beta"),
    (["alpha=t", "beta=0", "Zo=1", "gama=0"], {}, "did you mean 'gamma'"),
    (["alpha=t", "alpha=2", "beta=0", "Zo=1"], {}, "given twice for alpha"),
    (["alpha=t", "beta=sin(x)", "Zo=1"], {}, "beta: expression 'sin(x)': unknown name 'x'"),
    (["alpha t"], {}, "NAME=EXPRESSION"),
    (["alpha=", "beta=0", "Zo=1"], {}, "empty expression"),
    (["alpha=t", "beta=0", "Zo=1"], {"samples": 0}, "samples must be from 1 to"),
    (["alpha=t", "beta=0", "Zo=1"], {"samples": 2.5}, "samples must be an integer"),
    (["alpha=t", "beta=0", "Zo=1"], {"t_range": (1.0, 0.0)}, "t range"),
    (["alpha=t", "beta=0", "Zo=1"], {"t_range": (0.0, float("nan"))}, "t range"),
    (["alpha=log(t)", "beta=0", "Zo=1"], {}, "alpha: expression 'log(t)' is infinite at t = 0"),
])
def test_expression_path_errors(exprs, kwargs, piece):
    with pytest.raises(InputError) as info:
        path_from_expressions(exprs, INDEP, **kwargs)
    assert piece in str(info.value), str(info.value)


def test_parse_assignment_splits_at_first_equals():
    assert parse_assignment("Zo = 70+30*t") == ("Zo", " 70+30*t")
    with pytest.raises(InputError):
        parse_assignment("1x=2")


def test_cli_arguments(tmp_path):
    parser = argparse.ArgumentParser()
    add_path_arguments(parser)
    args = parser.parse_args(["--expr", "alpha=t", "--expr", "beta=0", "--expr", "Zo=80",
                              "--samples", "4", "--t-range", "0", "3"])
    path = path_from_args(args, INDEP)
    np.testing.assert_array_equal(path.t, [0.0, 1.0, 2.0, 3.0])
    csv = _csv(tmp_path, "t,alpha,beta,Zo\n0,0,0,80\n")
    assert path_from_args(parser.parse_args(["--path", str(csv)]), INDEP).n_samples == 1
    with pytest.raises(InputError, match="not both"):
        path_from_args(parser.parse_args(["--path", str(csv), "--expr", "alpha=t"]), INDEP)
    with pytest.raises(InputError, match="no path given"):
        path_from_args(parser.parse_args([]), INDEP)
