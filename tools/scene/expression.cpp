#include "tools/scene/expression.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <initializer_list>
#include <limits>
#include <numbers>
#include <utility>

namespace csim {

namespace {

// ---------------------------------------------------------------------------------------------------
// Built-ins

using BuiltinApply = double (*)(std::span<const double>);

struct BuiltinFunction {
  std::string_view name;
  std::size_t min_args;
  std::size_t max_args;
  BuiltinApply apply;
};

constexpr std::size_t variadic = std::numeric_limits<std::size_t>::max();

// NaN in, NaN out: a NaN must reach the caller's finiteness check instead of being dropped by a
// comparison inside min/max/sign.
double sign_of(double x) {
  if (std::isnan(x)) return x;
  return x > 0.0 ? 1.0 : (x < 0.0 ? -1.0 : 0.0);
}

template <bool take_max>
double extremum_of(std::span<const double> a) {
  double best = a[0];
  for (double x : a) {
    if (std::isnan(x)) return x;
    best = take_max ? std::max(best, x) : std::min(best, x);
  }
  return best;
}

// clang-format off
const BuiltinFunction builtin_functions[] = {
    {"sqrt",  1, 1, [](std::span<const double> a) { return std::sqrt(a[0]); }},
    {"sin",   1, 1, [](std::span<const double> a) { return std::sin(a[0]); }},
    {"cos",   1, 1, [](std::span<const double> a) { return std::cos(a[0]); }},
    {"tan",   1, 1, [](std::span<const double> a) { return std::tan(a[0]); }},
    {"asin",  1, 1, [](std::span<const double> a) { return std::asin(a[0]); }},
    {"acos",  1, 1, [](std::span<const double> a) { return std::acos(a[0]); }},
    {"atan",  1, 1, [](std::span<const double> a) { return std::atan(a[0]); }},
    {"atan2", 2, 2, [](std::span<const double> a) { return std::atan2(a[0], a[1]); }},
    {"exp",   1, 1, [](std::span<const double> a) { return std::exp(a[0]); }},
    {"log",   1, 1, [](std::span<const double> a) { return std::log(a[0]); }},
    {"abs",   1, 1, [](std::span<const double> a) { return std::abs(a[0]); }},
    {"floor", 1, 1, [](std::span<const double> a) { return std::floor(a[0]); }},
    {"ceil",  1, 1, [](std::span<const double> a) { return std::ceil(a[0]); }},
    {"sign",  1, 1, [](std::span<const double> a) { return sign_of(a[0]); }},
    {"pow",   2, 2, [](std::span<const double> a) { return std::pow(a[0], a[1]); }},
    {"min",   1, variadic, extremum_of<false>},
    {"max",   1, variadic, extremum_of<true>},
};
// clang-format on

struct BuiltinConstant {
  std::string_view name;
  double value;
};

const BuiltinConstant builtin_constants[] = {{"pi", std::numbers::pi}, {"e", std::numbers::e}};

const BuiltinFunction* find_builtin_function(std::string_view name) {
  for (const auto& f : builtin_functions)
    if (f.name == name) return &f;
  return nullptr;
}

const BuiltinConstant* find_builtin_constant(std::string_view name) {
  for (const auto& c : builtin_constants)
    if (c.name == name) return &c;
  return nullptr;
}

std::string arity_text(const BuiltinFunction& f) {
  if (f.max_args == variadic) return "at least " + std::to_string(f.min_args) + " argument" + (f.min_args == 1 ? "" : "s");
  return std::to_string(f.min_args) + " argument" + (f.min_args == 1 ? "" : "s");
}

// Every error names the place: the 1-based column and the whole text, so a message read in a scene-load
// log points at the faulty character without the scene file at hand.
ExpressionError error_at(std::string_view what, int column, std::string_view text, std::string_view detail = {}) {
  std::string message(what);
  message += " at column " + std::to_string(column) + " in '" + std::string(text) + "'";
  if (!detail.empty()) message += ", " + std::string(detail);
  return ExpressionError(message);
}

// ---------------------------------------------------------------------------------------------------
// Tokens

enum class TokenKind { number, name, op, end };

struct Token {
  TokenKind kind;
  std::string_view text;  // for the end token: empty
  double value = 0.0;     // numbers only
  int column = 0;         // 1-based
};

std::string describe(const Token& token) {
  return token.kind == TokenKind::end ? std::string("end of expression") : "'" + std::string(token.text) + "'";
}

bool is_name_start(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
bool is_name_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.'; }
bool is_digit(char c) { return c >= '0' && c <= '9'; }

class Lexer {
 public:
  explicit Lexer(std::string_view text) : text_(text) {}

  std::vector<Token> tokens() {
    std::vector<Token> out;
    for (;;) {
      while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
      if (pos_ == text_.size()) break;
      out.push_back(next());
    }
    out.push_back({TokenKind::end, {}, 0.0, static_cast<int>(text_.size()) + 1});
    return out;
  }

 private:
  Token next() {
    const std::size_t start = pos_;
    const char c = text_[pos_];
    if (is_digit(c) || (c == '.' && pos_ + 1 < text_.size() && is_digit(text_[pos_ + 1]))) return number();
    if (is_name_start(c)) {
      while (pos_ < text_.size() && is_name_char(text_[pos_])) ++pos_;
      return {TokenKind::name, text_.substr(start, pos_ - start), 0.0, column(start)};
    }
    static constexpr std::string_view two_char_ops[] = {"<=", ">=", "==", "!=", "&&", "||"};
    for (auto op : two_char_ops) {
      if (text_.substr(pos_, 2) == op) {
        pos_ += 2;
        return {TokenKind::op, op, 0.0, column(start)};
      }
    }
    static constexpr std::string_view one_char_ops = "+-*/^<>!(),";
    if (one_char_ops.find(c) != std::string_view::npos) {
      ++pos_;
      return {TokenKind::op, text_.substr(start, 1), 0.0, column(start)};
    }
    const std::string found = "unexpected character '" + std::string(1, c) + "'";
    if (c == '=') throw error_at(found, column(start), text_, "use '==' to compare");
    if (c == '&') throw error_at(found, column(start), text_, "use '&&'");
    if (c == '|') throw error_at(found, column(start), text_, "use '||'");
    throw error_at(found, column(start), text_);
  }

  Token number() {
    const std::size_t start = pos_;
    auto digits = [&] {
      while (pos_ < text_.size() && is_digit(text_[pos_])) ++pos_;
    };
    digits();
    if (pos_ < text_.size() && text_[pos_] == '.') {
      ++pos_;
      digits();
    }
    bool malformed = false;
    if (pos_ < text_.size() && (text_[pos_] == 'e' || text_[pos_] == 'E')) {
      ++pos_;
      if (pos_ < text_.size() && (text_[pos_] == '+' || text_[pos_] == '-')) ++pos_;
      const std::size_t exponent_start = pos_;
      digits();
      malformed = pos_ == exponent_start;
    }
    // A number glued to a name character ("2x", "1.2.3", "1e") is never valid: there is no implicit
    // multiplication, so report the whole run rather than a puzzling "unexpected name".
    while (pos_ < text_.size() && is_name_char(text_[pos_])) {
      ++pos_;
      malformed = true;
    }
    const std::string_view spelled = text_.substr(start, pos_ - start);
    double value = 0.0;
    if (!malformed) {
      const auto [end, ec] = std::from_chars(spelled.data(), spelled.data() + spelled.size(), value);
      malformed = ec == std::errc::invalid_argument || end != spelled.data() + spelled.size();
      // Out of range: from_chars leaves value untouched; IEEE overflow to inf is the documented behaviour.
      if (ec == std::errc::result_out_of_range) value = std::strtod(std::string(spelled).c_str(), nullptr);
    }
    if (malformed) throw error_at("malformed number '" + std::string(spelled) + "'", column(start), text_);
    return {TokenKind::number, spelled, value, column(start)};
  }

  int column(std::size_t pos) const { return static_cast<int>(pos) + 1; }

  std::string_view text_;
  std::size_t pos_ = 0;
};

}  // namespace

// ---------------------------------------------------------------------------------------------------
// Tree

enum class BinaryOp {
  add, subtract, multiply, divide, less, less_equal, greater, greater_equal, equal, not_equal, logical_and, logical_or
};

// A left-associative level is one chain node, `a - b + c` = operands [a, b, c] joined by [-, +], evaluated
// in a loop: as a binary tree, a chain of 10^5 terms nested 10^5 deep and overflowed the stack when
// evaluated or destroyed. The tree's depth is then bounded by the parser's nesting guard.
struct Expression::Node {
  enum class Kind { number, constant, variable, call, negate, logical_not, power, chain };

  Kind kind = Kind::number;
  double value = 0.0;                        // number, or the built-in constant's value
  std::string name;                          // constant, variable, call
  const BuiltinFunction* builtin = nullptr;  // call of a built-in function
  int column = 0;                            // of the token that produced the node
  std::vector<Node> children;                // operands or arguments
  std::vector<BinaryOp> operators;           // chain: operators[i] joins children[i] and children[i + 1]
};

namespace {

using Node = Expression::Node;

class Parser {
 public:
  explicit Parser(std::string_view text) : text_(text), tokens_(Lexer(text).tokens()) {}

  Node parse() {
    Node root = logical_or();
    if (peek().kind != TokenKind::end) throw error_at("unexpected " + describe(peek()), peek().column, text_);
    return root;
  }

  std::vector<std::string> names() {
    std::sort(names_.begin(), names_.end());
    names_.erase(std::unique(names_.begin(), names_.end()), names_.end());
    return std::move(names_);
  }

 private:
  const Token& peek() const { return tokens_[index_]; }
  bool at_op(std::string_view op) const { return peek().kind == TokenKind::op && peek().text == op; }
  const Token& advance() { return tokens_[index_++]; }

  void expect(std::string_view op) {
    if (!at_op(op)) throw error_at("expected '" + std::string(op) + "'", peek().column, text_, "found " + describe(peek()));
    advance();
  }

  // One left-associative precedence level: `operand` parses the next level up, `ops` maps spellings.
  template <typename Next>
  Node chain(Next operand, std::initializer_list<std::pair<std::string_view, BinaryOp>> ops) {
    auto match = [&] {
      return std::find_if(ops.begin(), ops.end(), [&](const auto& entry) { return at_op(entry.first); });
    };
    Node first = (this->*operand)();
    if (match() == ops.end()) return first;
    Node node;
    node.kind = Node::Kind::chain;
    node.column = peek().column;
    node.children.push_back(std::move(first));
    for (auto op = match(); op != ops.end(); op = match()) {
      advance();
      node.operators.push_back(op->second);
      node.children.push_back((this->*operand)());
    }
    return node;
  }

  Node logical_or() { return chain(&Parser::logical_and, {{"||", BinaryOp::logical_or}}); }

  Node logical_and() { return chain(&Parser::equality, {{"&&", BinaryOp::logical_and}}); }

  Node equality() { return chain(&Parser::comparison, {{"==", BinaryOp::equal}, {"!=", BinaryOp::not_equal}}); }

  Node comparison() {
    return chain(&Parser::sum, {{"<=", BinaryOp::less_equal},
                                {">=", BinaryOp::greater_equal},
                                {"<", BinaryOp::less},
                                {">", BinaryOp::greater}});
  }

  Node sum() { return chain(&Parser::product, {{"+", BinaryOp::add}, {"-", BinaryOp::subtract}}); }

  Node product() { return chain(&Parser::unary, {{"*", BinaryOp::multiply}, {"/", BinaryOp::divide}}); }

  // Every recursion of the grammar passes through here; the bound turns a pathological input such as
  // 10^5 '(' into an error instead of a stack overflow.
  Node unary() {
    if (++depth_ > max_depth) throw error_at("expression nested too deeply", peek().column, text_);
    Node node = unary_unbounded();
    --depth_;
    return node;
  }

  Node unary_unbounded() {
    if (at_op("-") || at_op("!")) {
      Node node;
      node.kind = at_op("-") ? Node::Kind::negate : Node::Kind::logical_not;
      node.column = advance().column;
      node.children.push_back(unary());
      return node;
    }
    if (at_op("+")) {
      advance();
      return unary();
    }
    return power();
  }

  // The exponent is a unary so that 2^-1 parses; the base is a primary so that -2^2 = -(2^2).
  Node power() {
    Node base = primary();
    if (!at_op("^")) return base;
    Node node;
    node.kind = Node::Kind::power;
    node.column = advance().column;
    node.children.push_back(std::move(base));
    node.children.push_back(unary());
    return node;
  }

  Node primary() {
    const Token& token = peek();
    if (token.kind == TokenKind::number) {
      advance();
      Node node;
      node.kind = Node::Kind::number;
      node.value = token.value;
      node.column = token.column;
      return node;
    }
    if (token.kind == TokenKind::name) return name_or_call();
    if (at_op("(")) {
      advance();
      Node inner = logical_or();
      expect(")");
      return inner;
    }
    throw error_at("expected a number, a name or '('", token.column, text_, "found " + describe(token));
  }

  Node name_or_call() {
    const Token& token = advance();
    Node node;
    node.name = std::string(token.text);
    node.column = token.column;
    // A name is the scope's unless it is a built-in of the same kind: 'max' as a variable is the scope's.
    if (!at_op("(")) {
      const BuiltinConstant* constant = find_builtin_constant(node.name);
      node.kind = constant ? Node::Kind::constant : Node::Kind::variable;
      if (constant)
        node.value = constant->value;
      else
        names_.push_back(node.name);
      return node;
    }
    advance();
    node.kind = Node::Kind::call;
    node.builtin = find_builtin_function(node.name);
    if (!node.builtin) names_.push_back(node.name);
    if (!at_op(")")) {
      node.children.push_back(logical_or());
      while (at_op(",")) {
        advance();
        node.children.push_back(logical_or());
      }
    }
    expect(")");
    return node;
  }

  std::string_view text_;
  std::vector<Token> tokens_;
  std::size_t index_ = 0;
  std::vector<std::string> names_;
  int depth_ = 0;
  static constexpr int max_depth = 256;
};

// ---------------------------------------------------------------------------------------------------
// Evaluation

class Evaluator {
 public:
  Evaluator(const ExpressionScope& scope, std::string_view text) : scope_(scope), text_(text) {}

  double operator()(const Node& node) const {
    switch (node.kind) {
      case Node::Kind::number: return node.value;
      case Node::Kind::constant: return constant(node);
      case Node::Kind::variable: return variable(node);
      case Node::Kind::call: return call(node);
      case Node::Kind::negate: return -(*this)(node.children[0]);
      case Node::Kind::logical_not: return truth((*this)(node.children[0])) ? 0.0 : 1.0;
      case Node::Kind::power: return std::pow((*this)(node.children[0]), (*this)(node.children[1]));
      case Node::Kind::chain: return chain(node);
    }
    return std::numeric_limits<double>::quiet_NaN();  // unreachable: all kinds handled above
  }

 private:
  static bool truth(double x) { return x != 0.0; }

  // Left to right; && and || skip their right operand as C does, so that a guard such as
  // `shoe.extremum_count() >= 2 && shoe.extremum(2) > 0` never calls what it guards against.
  double chain(const Node& node) const {
    double value = (*this)(node.children[0]);
    for (std::size_t i = 1; i < node.children.size(); ++i) {
      const Node& operand = node.children[i];
      const BinaryOp op = node.operators[i - 1];
      if (op == BinaryOp::logical_and) value = truth(value) && truth((*this)(operand)) ? 1.0 : 0.0;
      else if (op == BinaryOp::logical_or) value = truth(value) || truth((*this)(operand)) ? 1.0 : 0.0;
      else value = binary(op, value, (*this)(operand));
    }
    return value;
  }

  static double binary(BinaryOp op, double a, double b) {
    switch (op) {
      case BinaryOp::add: return a + b;
      case BinaryOp::subtract: return a - b;
      case BinaryOp::multiply: return a * b;
      case BinaryOp::divide: return a / b;
      case BinaryOp::less: return a < b ? 1.0 : 0.0;
      case BinaryOp::less_equal: return a <= b ? 1.0 : 0.0;
      case BinaryOp::greater: return a > b ? 1.0 : 0.0;
      case BinaryOp::greater_equal: return a >= b ? 1.0 : 0.0;
      case BinaryOp::equal: return a == b ? 1.0 : 0.0;
      case BinaryOp::not_equal: return a != b ? 1.0 : 0.0;
      case BinaryOp::logical_and:
      case BinaryOp::logical_or: break;  // short-circuit: chain() evaluates them
    }
    return std::numeric_limits<double>::quiet_NaN();
  }

  double constant(const Node& node) const {
    if (scope_.variables.count(node.name))
      throw error_at("built-in constant '" + node.name + "' is redefined by the scope", node.column, text_);
    return node.value;
  }

  double variable(const Node& node) const {
    if (const auto it = scope_.variables.find(node.name); it != scope_.variables.end()) return it->second;
    if (scope_.functions.count(node.name) || find_builtin_function(node.name))
      throw error_at("'" + node.name + "' is a function, not a variable,", node.column, text_, "call it with arguments");
    throw error_at("unknown name '" + node.name + "'", node.column, text_);
  }

  double call(const Node& node) const {
    std::vector<double> args;
    args.reserve(node.children.size());
    if (node.builtin) {
      if (scope_.functions.count(node.name))
        throw error_at("built-in function '" + node.name + "' is redefined by the scope", node.column, text_);
      const BuiltinFunction& f = *node.builtin;
      if (node.children.size() < f.min_args || node.children.size() > f.max_args)
        throw error_at("function '" + node.name + "' takes " + arity_text(f) + ", got " +
                           std::to_string(node.children.size()),
                       node.column, text_);
      for (const Node& arg : node.children) args.push_back((*this)(arg));
      return f.apply(args);
    }
    const auto it = scope_.functions.find(node.name);
    if (it == scope_.functions.end()) {
      if (scope_.variables.count(node.name) || find_builtin_constant(node.name))
        throw error_at("'" + node.name + "' is a variable, not a function,", node.column, text_);
      throw error_at("unknown function '" + node.name + "'", node.column, text_);
    }
    for (const Node& arg : node.children) args.push_back((*this)(arg));
    try {
      return it->second(args);
    } catch (const std::exception& failure) {
      throw ExpressionFunctionFailed(
          error_at("function '" + node.name + "' failed", node.column, text_, failure.what()).what());
    }
  }

  const ExpressionScope& scope_;
  std::string_view text_;
};

}  // namespace

Expression::Expression(std::string text, std::shared_ptr<const Node> root, std::vector<std::string> names)
    : text_(std::move(text)), root_(std::move(root)), names_(std::move(names)) {}

Expression Expression::parse(std::string_view text) {
  Parser parser(text);
  auto root = std::make_shared<const Node>(parser.parse());
  return Expression(std::string(text), std::move(root), parser.names());
}

double Expression::evaluate(const ExpressionScope& scope) const { return Evaluator(scope, text_)(*root_); }

std::vector<std::string> Expression::names() const { return names_; }

const std::string& Expression::text() const { return text_; }

double evaluate_expression(std::string_view text, const ExpressionScope& scope) {
  return Expression::parse(text).evaluate(scope);
}

bool is_builtin_name(std::string_view name) {
  return find_builtin_function(name) != nullptr || find_builtin_constant(name) != nullptr;
}

}  // namespace csim
