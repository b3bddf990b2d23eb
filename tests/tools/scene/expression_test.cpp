#include "tools/scene/expression.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace csim {
namespace {

double eval(std::string_view text, const ExpressionScope& scope = {}) { return evaluate_expression(text, scope); }

// The message of the ExpressionError thrown by `action`, or a failure if nothing is thrown.
template <typename Action>
std::string error_message(Action action) {
  try {
    action();
  } catch (const ExpressionError& error) {
    return error.what();
  }
  ADD_FAILURE() << "no ExpressionError thrown";
  return {};
}

std::string parse_error(std::string_view text) {
  return error_message([&] { Expression::parse(text); });
}

std::string evaluation_error(std::string_view text, const ExpressionScope& scope = {}) {
  const Expression expression = Expression::parse(text);  // must parse: the error is an evaluation one
  return error_message([&] { expression.evaluate(scope); });
}

TEST(Expression, Numbers) {
  EXPECT_EQ(eval("12"), 12.0);
  EXPECT_EQ(eval("1.5"), 1.5);
  EXPECT_EQ(eval(".5"), 0.5);
  EXPECT_EQ(eval("5."), 5.0);
  EXPECT_EQ(eval("1e-3"), 1e-3);
  EXPECT_EQ(eval("2.5E+2"), 250.0);
  EXPECT_EQ(eval("  7 "), 7.0);
  EXPECT_TRUE(std::isinf(eval("1e400")));
}

TEST(Expression, PrecedenceAndAssociativity) {
  EXPECT_EQ(eval("1+2*3"), 7.0);
  EXPECT_EQ(eval("(1+2)*3"), 9.0);
  EXPECT_EQ(eval("10-4-3"), 3.0);
  EXPECT_EQ(eval("64/4/2"), 8.0);
  EXPECT_EQ(eval("2*3/4"), 1.5);
  EXPECT_EQ(eval("2^3^2"), 512.0);  // right-associative: 2^(3^2)
  EXPECT_EQ(eval("(2^3)^2"), 64.0);
  EXPECT_EQ(eval("2*3^2"), 18.0);
  EXPECT_EQ(eval("1+2 < 4"), 1.0);  // comparisons below arithmetic
  EXPECT_EQ(eval("1 < 2 == 1"), 1.0);  // equality below ordering
  EXPECT_EQ(eval("1 || 0 && 0"), 1.0);  // && binds tighter than ||
  EXPECT_EQ(eval("(1 || 0) && 0"), 0.0);
}

TEST(Expression, UnaryOperatorsAndPower) {
  EXPECT_EQ(eval("-2^2"), -4.0);
  EXPECT_EQ(eval("(-2)^2"), 4.0);
  EXPECT_EQ(eval("2^-1"), 0.5);
  EXPECT_EQ(eval("2^-2^2"), 1.0 / 16.0);  // 2^(-(2^2))
  EXPECT_EQ(eval("--3"), 3.0);
  EXPECT_EQ(eval("+3"), 3.0);
  EXPECT_EQ(eval("-3*-2"), 6.0);
  EXPECT_EQ(eval("1 - -1"), 2.0);
  EXPECT_EQ(eval("!0"), 1.0);
  EXPECT_EQ(eval("!2"), 0.0);
  EXPECT_EQ(eval("!!5"), 1.0);
}

TEST(Expression, Builtins) {
  constexpr double pi = std::numbers::pi;
  EXPECT_EQ(eval("pi"), pi);
  EXPECT_EQ(eval("e"), std::numbers::e);
  EXPECT_EQ(eval("sqrt(16)"), 4.0);
  EXPECT_DOUBLE_EQ(eval("sin(pi/6)"), 0.5);
  EXPECT_DOUBLE_EQ(eval("cos(pi/3)"), 0.5);
  EXPECT_DOUBLE_EQ(eval("tan(pi/4)"), 1.0);
  EXPECT_DOUBLE_EQ(eval("asin(1)"), pi / 2);
  EXPECT_DOUBLE_EQ(eval("acos(-1)"), pi);
  EXPECT_DOUBLE_EQ(eval("atan(1)"), pi / 4);
  EXPECT_DOUBLE_EQ(eval("atan2(1, -1)"), 3 * pi / 4);
  EXPECT_DOUBLE_EQ(eval("exp(1)"), std::numbers::e);
  EXPECT_DOUBLE_EQ(eval("log(e^2)"), 2.0);
  EXPECT_EQ(eval("abs(-3.5)"), 3.5);
  EXPECT_EQ(eval("min(3)"), 3.0);
  EXPECT_EQ(eval("min(3, -1, 2)"), -1.0);
  EXPECT_EQ(eval("max(3, -1, 7, 2)"), 7.0);
  EXPECT_TRUE(std::isnan(eval("max(1, sqrt(-1))")));  // NaN is not dropped by max
  EXPECT_EQ(eval("pow(2, 10)"), 1024.0);
  EXPECT_EQ(eval("floor(-1.5)"), -2.0);
  EXPECT_EQ(eval("ceil(-1.5)"), -1.0);
  EXPECT_EQ(eval("sign(-0.2)"), -1.0);
  EXPECT_EQ(eval("sign(0)"), 0.0);
  EXPECT_EQ(eval("sign(3)"), 1.0);
  EXPECT_EQ(eval("sqrt(max(0, 2) + 2)"), 2.0);  // nested calls
}

TEST(Expression, DivisionByZeroFollowsIeee) {
  EXPECT_EQ(eval("1/0"), std::numeric_limits<double>::infinity());
  EXPECT_EQ(eval("-1/0"), -std::numeric_limits<double>::infinity());
  EXPECT_TRUE(std::isnan(eval("0/0")));
}

TEST(Expression, SceneStyleFormulas) {
  ExpressionScope scope;
  scope.variables = {{"push_force", 200000.0}, {"mu", 0.3},  {"normal_force", 70000.0}, {"stiffness", 24000.0},
                     {"mass", 7000.0},         {"n", 2.0},   {"restitution", 0.5},      {"h0", 1.0},
                     {"gravity", 9.81},        {"angle", 30}, {"t", 2.0}};
  EXPECT_DOUBLE_EQ(eval("2*(push_force - mu*normal_force)/stiffness", scope), 2 * (200000.0 - 21000.0) / 24000.0);
  EXPECT_DOUBLE_EQ(eval("pi*sqrt(mass/stiffness)", scope), std::numbers::pi * std::sqrt(7000.0 / 24000.0));
  EXPECT_DOUBLE_EQ(eval("restitution^(2*n)*h0", scope), 0.0625);
  const double angle = 30 * std::numbers::pi / 180;
  EXPECT_DOUBLE_EQ(eval("0.5*gravity*max(0, sin(angle*pi/180) - mu*cos(angle*pi/180))*t^2", scope),
                   0.5 * 9.81 * std::max(0.0, std::sin(angle) - 0.3 * std::cos(angle)) * 4.0);
}

TEST(Expression, VariablesAndUserFunctions) {
  ExpressionScope scope;
  scope.variables["x"] = 3.0;
  scope.variables["shoe.mass"] = 7000.0;
  scope.functions["shoe.extremum"] = [](std::span<const double> args) { return 10.0 * args[0]; };
  scope.functions["sum"] = [](std::span<const double> args) {
    double total = 0;
    for (double a : args) total += a;
    return total;
  };
  scope.functions["answer"] = [](std::span<const double> args) { return args.empty() ? 42.0 : -1.0; };
  EXPECT_EQ(eval("x*x", scope), 9.0);
  EXPECT_EQ(eval("shoe.mass/1000", scope), 7.0);
  EXPECT_EQ(eval("shoe.extremum(1)", scope), 10.0);
  EXPECT_EQ(eval("shoe.extremum(x - 1) + 1", scope), 21.0);
  EXPECT_EQ(eval("sum(1, 2, x, sum(4))", scope), 10.0);
  EXPECT_EQ(eval("answer()", scope), 42.0);

  // Parsed once, evaluated with different scopes.
  const Expression expression = Expression::parse("2*x + 1");
  EXPECT_EQ(expression.evaluate(scope), 7.0);
  scope.variables["x"] = -1.0;
  EXPECT_EQ(expression.evaluate(scope), -1.0);
  EXPECT_EQ(expression.text(), "2*x + 1");
}

TEST(Expression, ComparisonsAndLogic) {
  ExpressionScope scope;
  scope.variables["mu"] = 0.1 + 1e-14;
  EXPECT_EQ(eval("abs(mu - 0.1) < 1e-12", scope), 1.0);
  EXPECT_EQ(eval("abs(mu - 0.1) < 1e-15", scope), 0.0);
  EXPECT_EQ(eval("1 < 2"), 1.0);
  EXPECT_EQ(eval("2 < 2"), 0.0);
  EXPECT_EQ(eval("2 <= 2"), 1.0);
  EXPECT_EQ(eval("3 > 2"), 1.0);
  EXPECT_EQ(eval("2 >= 3"), 0.0);
  EXPECT_EQ(eval("2 == 2"), 1.0);
  EXPECT_EQ(eval("2 != 2"), 0.0);
  EXPECT_EQ(eval("1 && 2"), 1.0);
  EXPECT_EQ(eval("1 && 0"), 0.0);
  EXPECT_EQ(eval("0 || 0"), 0.0);
  EXPECT_EQ(eval("0 || -3"), 1.0);
  EXPECT_EQ(eval("!(1 < 2) || 2 > 1"), 1.0);
  // Short-circuit: the unknown name on the right is never evaluated.
  EXPECT_EQ(eval("0 && undefined_name"), 0.0);
  EXPECT_EQ(eval("1 || undefined_name"), 1.0);
}

TEST(Expression, NamesListsScopeNamesOnly) {
  const Expression expression =
      Expression::parse("shoe.extremum(1) + mu*sqrt(mass/k) - pi + mu*e + max(a, b.c) + f()");
  const std::vector<std::string> expected = {"a", "b.c", "f", "k", "mass", "mu", "shoe.extremum"};
  EXPECT_EQ(expression.names(), expected);
  EXPECT_TRUE(Expression::parse("2*pi").names().empty());
  // A built-in function's name in variable position is the scope's, and resolved from it.
  EXPECT_EQ(Expression::parse("max*2").names(), std::vector<std::string>{"max"});
  ExpressionScope scope;
  scope.variables["max"] = 4.0;
  EXPECT_EQ(eval("max*max(1, 2)", scope), 8.0);
  EXPECT_TRUE(is_builtin_name("pi"));
  EXPECT_TRUE(is_builtin_name("atan2"));
  EXPECT_FALSE(is_builtin_name("mu"));
}

TEST(ExpressionErrors, UnknownName) {
  const std::string message = evaluation_error("2*mux");
  EXPECT_NE(message.find("unknown name 'mux'"), std::string::npos) << message;
  EXPECT_NE(message.find("column 3"), std::string::npos) << message;
  EXPECT_NE(message.find("'2*mux'"), std::string::npos) << message;

  const std::string function_message = evaluation_error("1 + shoe.extremm(1)");
  EXPECT_NE(function_message.find("unknown function 'shoe.extremm'"), std::string::npos) << function_message;
  EXPECT_NE(function_message.find("column 5"), std::string::npos) << function_message;
}

TEST(ExpressionErrors, WrongKindOfName) {
  ExpressionScope scope;
  scope.variables["mu"] = 0.3;
  scope.functions["f"] = [](std::span<const double>) { return 0.0; };
  const std::string called_variable = evaluation_error("mu(2)", scope);
  EXPECT_NE(called_variable.find("'mu' is a variable, not a function"), std::string::npos) << called_variable;
  const std::string bare_function = evaluation_error("1 + f", scope);
  EXPECT_NE(bare_function.find("'f' is a function, not a variable"), std::string::npos) << bare_function;
  EXPECT_NE(bare_function.find("column 5"), std::string::npos) << bare_function;
  const std::string bare_builtin = evaluation_error("sqrt");
  EXPECT_NE(bare_builtin.find("'sqrt' is a function"), std::string::npos) << bare_builtin;
}

TEST(ExpressionErrors, ScopeMayNotShadowBuiltins) {
  ExpressionScope scope;
  scope.variables["e"] = 0.8;  // e.g. a restitution coefficient: must not silently become 2.718
  const std::string message = evaluation_error("e*2", scope);
  EXPECT_NE(message.find("'e'"), std::string::npos) << message;
  EXPECT_NE(message.find("column 1"), std::string::npos) << message;
  ExpressionScope functions;
  functions.functions["sqrt"] = [](std::span<const double>) { return 0.0; };
  EXPECT_NE(evaluation_error("sqrt(4)", functions).find("'sqrt'"), std::string::npos);
}

TEST(ExpressionErrors, Arity) {
  const std::string message = evaluation_error("1 + sqrt(1, 2)");
  EXPECT_NE(message.find("function 'sqrt' takes 1 argument, got 2"), std::string::npos) << message;
  EXPECT_NE(message.find("column 5"), std::string::npos) << message;
  EXPECT_NE(evaluation_error("atan2(1)").find("function 'atan2' takes 2 arguments, got 1"), std::string::npos);
  EXPECT_NE(evaluation_error("max()").find("function 'max' takes at least 1 argument, got 0"), std::string::npos);
}

TEST(ExpressionErrors, UserFunctionFailureIsReportedWithItsPlace) {
  ExpressionScope scope;
  scope.functions["shoe.extremum"] = [](std::span<const double> args) -> double {
    throw std::out_of_range("extremum index " + std::to_string(static_cast<int>(args[0])) + " out of range");
  };
  const std::string message = evaluation_error("2*shoe.extremum(9)", scope);
  EXPECT_NE(message.find("'shoe.extremum'"), std::string::npos) << message;
  EXPECT_NE(message.find("column 3"), std::string::npos) << message;
  EXPECT_NE(message.find("extremum index 9 out of range"), std::string::npos) << message;
}

TEST(ExpressionErrors, Syntax) {
  struct Case {
    std::string_view text;
    std::string_view expected;  // both the problem and the offending token
    std::string_view column;
  };
  const Case cases[] = {
      {"(1+2", "expected ')'", "column 5"},
      {"(1+2", "found end of expression", "column 5"},
      {"max(1, 2", "expected ')'", "column 9"},
      {"1+*2", "found '*'", "column 3"},
      {"", "expected a number, a name or '('", "column 1"},
      {"1 2", "unexpected '2'", "column 3"},
      {"1+2)", "unexpected ')'", "column 4"},
      {"f(1,)", "found ')'", "column 5"},
      {"2x", "malformed number '2x'", "column 1"},
      {"1e+", "malformed number '1e+'", "column 1"},
      {"1.2.3", "malformed number '1.2.3'", "column 1"},
      {"a = 2", "unexpected character '='", "column 3"},
      {"a & b", "unexpected character '&'", "column 3"},
      {"3 # 4", "unexpected character '#'", "column 3"},
  };
  for (const Case& c : cases) {
    const std::string message = parse_error(c.text);
    EXPECT_NE(message.find(c.expected), std::string::npos) << c.text << " -> " << message;
    EXPECT_NE(message.find(c.column), std::string::npos) << c.text << " -> " << message;
  }
}

TEST(ExpressionErrors, DeepNestingIsAnErrorNotACrash) {
  const std::string deep = std::string(100000, '(') + "1" + std::string(100000, ')');
  EXPECT_NE(parse_error(deep).find("nested too deeply"), std::string::npos);
  const std::string fine = std::string(100, '(') + "1" + std::string(100, ')');
  EXPECT_EQ(eval(fine), 1.0);
}

// A chain of one precedence level is a loop, not a nesting: long ones parse, evaluate left to right and
// are destroyed without a stack frame per term (64 000 terms overflowed the stack, issue 29).
std::string repeated(std::string_view piece, int count) {
  std::string text;
  for (int i = 0; i < count; ++i) text += piece;
  return text;
}

TEST(Expression, LongChainsOfBinaryOperators) {
  EXPECT_EQ(eval(repeated("0+", 64000) + "0.3"), 0.3);
  EXPECT_EQ(eval("100000" + repeated("-1", 100000)), 0.0);  // left to right: ((100000-1)-1)-...
  EXPECT_EQ(eval("1" + repeated("*2/2", 50000)), 1.0);
  EXPECT_EQ(eval("0" + repeated("<1", 100001)), 1.0);  // 0<1 = 1, 1<1 = 0, ...: odd count gives 1
  EXPECT_EQ(eval("1" + repeated("==1", 100000)), 1.0);
  EXPECT_EQ(eval(repeated("1&&", 100000) + "1"), 1.0);
  EXPECT_EQ(eval(repeated("0||", 100000) + "0"), 0.0);
  ExpressionScope scope;
  scope.variables["x"] = 0.5;
  EXPECT_EQ(eval(repeated("x+", 100000) + "x", scope), 50000.5);
  // Parsed and dropped: destroying the tree must not recurse per term either.
  EXPECT_TRUE(Expression::parse(repeated("1+", 1000000) + "1").names().empty());
}

TEST(Expression, ChainsInsideTheNestingLimit) {
  EXPECT_EQ(eval(repeated("(1+", 250) + "1" + std::string(250, ')')), 251.0);
  EXPECT_EQ(eval(repeated("-(1-", 100) + "1" + std::string(100, ')')), -99.0);  // v = -(1 - v), 100 times from 1
  EXPECT_NE(parse_error(repeated("(1+", 300) + "1" + std::string(300, ')')).find("nested too deeply"),
            std::string::npos);
}

TEST(Expression, LogicalChainsShortCircuit) {
  int calls = 0;
  ExpressionScope scope;
  scope.functions["f"] = [&](std::span<const double>) { ++calls; return 1.0; };
  EXPECT_EQ(eval("1 && 0 && f() && f()", scope), 0.0);
  EXPECT_EQ(eval("0 || 1 || f()", scope), 1.0);
  EXPECT_EQ(calls, 0);
  EXPECT_EQ(eval("1 && f() && 1", scope), 1.0);
  EXPECT_EQ(calls, 1);
}

}  // namespace
}  // namespace csim
