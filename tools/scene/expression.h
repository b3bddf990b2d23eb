// Arithmetic expressions in scene files. Any numeric scene value may be written as a string that starts
// with '=' (the caller strips the '='), e.g. "pi*sqrt(mass/stiffness)" or "shoe.extremum(1)".
//
// Grammar, lowest precedence first (all binary operators left-associative except '^'):
//   or      := and ('||' and)*
//   and     := equal ('&&' equal)*
//   equal   := compare (('==' | '!=') compare)*
//   compare := sum (('<' | '<=' | '>' | '>=') sum)*
//   sum     := product (('+' | '-') product)*
//   product := unary (('*' | '/') unary)*
//   unary   := ('-' | '+' | '!') unary | power
//   power   := primary ('^' unary)?            right-associative and above unary minus: -2^2 = -4, 2^-1 = 0.5
//   primary := number | name | name '(' [or (',' or)*] ')' | '(' or ')'
// Nesting (parentheses, unary operators, '^', call arguments) is limited to 256 levels, a parse error
// beyond; a chain of one level (`a + b - c + ...`) has no length limit and costs no stack per term.
// Numbers: 12, 1.5, .5, 1e-3. Names: [A-Za-z_][A-Za-z0-9_.]* (a dot is part of the name, so
// 'shoe.extremum' is one name). Comparisons and logic give 1 or 0; any non-zero operand is true.
//
// Built-ins: constants pi, e; functions sqrt sin cos tan asin acos atan exp log abs floor ceil sign
// (1 argument), atan2 pow (2), min max (1 or more). Angles are in radians.
//
// Names are resolved at evaluation, from the built-ins and the scope. A built-in name cannot be
// redefined: a scope entry that shadows a built-in used by the expression is an error rather than a silent
// choice, so a scene parameter called 'e' cannot quietly turn into 2.718 (see is_builtin_name).
//
// Arithmetic follows IEEE 754: 1/0 gives inf and sqrt(-1) gives NaN. Checking for finite results is the
// caller's job, because only the caller knows which value is being defined.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace csim {

// The message gives the 1-based column, the offending token or name, and the expression text, e.g.
// "unknown name 'mux' at column 3 in '2*mux'".
struct ExpressionError : std::runtime_error {
  using runtime_error::runtime_error;
};

// A user function that threw: the expression is well formed, but what it refers to does not exist for
// these values (an analytical solution without a third extremum, say). Callers may treat this as
// "cannot be judged" rather than as bad input.
struct ExpressionFunctionFailed : ExpressionError {
  using ExpressionError::ExpressionError;
};

// A user function receives its evaluated arguments. It checks their count itself and may throw any
// std::exception; evaluate() reports it as an ExpressionError naming the function and its column.
using ExpressionFunction = std::function<double(std::span<const double>)>;

// What the names of an expression mean during evaluation.
struct ExpressionScope {
  std::map<std::string, double> variables;
  std::map<std::string, std::string> texts;  // text parameters (a choice among names), read as '=name'
  std::map<std::string, ExpressionFunction> functions;  // e.g. "shoe.extremum"
};

// Parsed once into a tree, then evaluated any number of times. Copies share the (immutable) tree.
class Expression {
 public:
  // Throws ExpressionError on a syntax error.
  static Expression parse(std::string_view text);

  // Throws ExpressionError on an unknown name, a variable called as a function or the reverse, a wrong
  // number of arguments to a built-in, a scope entry shadowing a built-in, or a failing user function.
  double evaluate(const ExpressionScope& scope) const;

  // The names the scope must provide (variables and user functions), sorted and unique. Built-ins are not
  // listed (a built-in function name used as a variable is). Useful to order the evaluation of
  // parameters that refer to each other.
  std::vector<std::string> names() const;

  const std::string& text() const;

  struct Node;  // implementation detail, defined in expression.cpp

 private:
  Expression(std::string text, std::shared_ptr<const Node> root, std::vector<std::string> names);

  std::string text_;
  std::shared_ptr<const Node> root_;
  std::vector<std::string> names_;
};

// Parses and evaluates in one call. Throws ExpressionError.
double evaluate_expression(std::string_view text, const ExpressionScope& scope);

// True for the built-in constants and functions, whose names a scope may not redefine.
bool is_builtin_name(std::string_view name);

}  // namespace csim
