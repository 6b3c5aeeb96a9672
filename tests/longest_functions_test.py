#!/usr/bin/env python3
"""raster/tools/longest_functions.py on C++ snippets whose functions' lines are counted by hand:
braces in comments, strings, character and raw string literals and macros do not count, nor do
control blocks, classes and braced initializers; lambdas are listed with their enclosing function;
the command line's --top, paths and errors.

    python3 tests/longest_functions_test.py
"""

import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
TOOL = os.path.join(HERE, "..", "raster", "tools", "longest_functions.py")
sys.path.insert(0, os.path.dirname(TOOL))
import longest_functions  # noqa: E402

# Line numbers on the right are the snippet's own (line 1 is the comment).
SNIPPET = r"""// Braces in comments { and strings do not count.
#include <string>
#define OPEN_BRACE {
#define MULTI(x) \
    do {         \
    } while (0)

namespace demo {

/* a block comment with a function: void fake() { } */
int add(int a, int b) {
    return a + b;
}

template <class T>
T twice(T x)
{
    const char* s = "} { \" }";
    const char c = '}';
    const char q = '\'';
    const int big = 1'000'000;
    const char* raw = R"x(
} } { ) "
)x";
    return x + x;
}

class Widget : public Base {
public:
    Widget(int a) : a_(a), b_{a, 2} {
        if (a > 0) {
            a_ = 1;
        }
    }
    int get() const { return a_; }
    bool operator==(const Widget& o) const {
        return a_ == o.a_;
    }
private:
    int a_;
    int b_[2];
};

int Widget::helper(std::vector<int> v) {
    int sum = 0;
    auto add_one = [&sum](int x) {
        sum += x + 1;
    };
    for (int x : v) {
        add_one(x);
    }
    std::for_each(v.begin(), v.end(), [](int) {});
    return sum;
}

auto trailing() -> decltype(add(1, 2)) {
    return 3;
}

}  // namespace demo
"""

# (name, first line, length in lines)
EXPECTED = [
    ("add", 11, 3),
    ("twice", 15, 12),  # from its template header to its brace
    ("Widget::Widget", 30, 5),
    ("Widget::get", 35, 1),
    ("Widget::operator==", 36, 3),
    ("lambda add_one in Widget::helper", 46, 3),
    ("lambda in Widget::helper", 52, 1),
    ("Widget::helper", 44, 11),
    ("trailing", 56, 3),
]

# Switch labels, an enum, an initialized array, a function-like macro's definition, a lambda
# initializing a variable at file scope and one in a struct, an operator(), a destructor, a
# template's specialization and a lambda without parameters returned by a function.
SNIPPET_MORE = r"""enum class Kind : unsigned char { A, B };
const int kTable[] = {1, 2, 3};
constexpr auto kSquare = [](int x) {
    return x * x;
};
struct Traits {
    static constexpr bool kWide = [] {
        return true;
    }();
    int operator()(int x) const {
        switch (x) {
            case 1: {
                return 2;
            }
            default:
                return 3;
        }
    }
    ~Traits() {}
};
template <>
int twice<int>(int x) { return 2 * x; }
auto maker() {
    return [x = 1] { return x; };
}
TEST(Suite, Name) {
    EXPECT_EQ(1, 1);
}
"""

EXPECTED_MORE = [
    ("lambda kSquare at file scope", 3, 3),
    ("lambda kWide in Traits", 7, 3),
    ("Traits::operator()", 10, 9),
    ("Traits::~Traits", 19, 1),
    ("twice", 21, 2),
    ("lambda in maker", 24, 1),
    ("maker", 23, 3),
    ("TEST(Suite, Name)", 26, 3),
]


def found(text):
    return [(f.name, f.line, f.length) for f in longest_functions.scan("snippet.cpp", text)]


class Scanner(unittest.TestCase):
    def test_functions_and_their_lengths(self):
        self.assertEqual(sorted(found(SNIPPET)), sorted(EXPECTED))

    def test_lambdas_labels_operators_and_macros(self):
        self.assertEqual(sorted(found(SNIPPET_MORE)), sorted(EXPECTED_MORE))

    def test_lambdas_are_marked(self):
        functions = longest_functions.scan("snippet.cpp", SNIPPET)
        self.assertEqual(sorted(f.name for f in functions if f.is_lambda),
                         ["lambda add_one in Widget::helper", "lambda in Widget::helper"])

    def test_blanking_keeps_lines_and_hides_literals(self):
        blanked = longest_functions.blank_code(SNIPPET)
        self.assertEqual(len(blanked), len(SNIPPET))
        self.assertEqual(blanked.count("\n"), SNIPPET.count("\n"))
        # The braces left are the code's: namespace, add, twice, class, constructor, b_{}, if, get,
        # operator==, helper, its two lambdas, for, trailing: 14 pairs.
        self.assertEqual(blanked.count("{"), 14)
        self.assertEqual(blanked.count("}"), 14)
        self.assertNotIn("fake", blanked)
        self.assertNotIn("OPEN_BRACE", blanked)

    def test_an_unmatched_brace_is_warned_about(self):
        warnings = []
        functions = longest_functions.scan("bad.cpp", "void f() {\n}\n}\nvoid g() {\n}\n", warnings.append)
        self.assertEqual([(f.name, f.line, f.length) for f in functions], [("f", 1, 2), ("g", 4, 2)])
        self.assertEqual(warnings, ["bad.cpp:3: unmatched '}'; braces after it may be misread"])
        warnings.clear()
        longest_functions.scan("open.cpp", "void f() {\n", warnings.append)
        self.assertEqual(warnings, ["open.cpp:1: '{' not closed by the end of the file"])


class CommandLine(unittest.TestCase):
    def run_tool(self, *args, cwd=None):
        return subprocess.run([sys.executable, TOOL, *args], cwd=cwd, capture_output=True, text=True)

    def test_top_lists_the_longest_first(self):
        with tempfile.TemporaryDirectory() as tmp:
            os.mkdir(os.path.join(tmp, "src"))
            with open(os.path.join(tmp, "src", "demo.cpp"), "w") as f:
                f.write(SNIPPET)
            with open(os.path.join(tmp, "src", "more.hpp"), "w") as f:
                f.write(SNIPPET_MORE)
            with open(os.path.join(tmp, "src", "notes.txt"), "w") as f:
                f.write("void skipped() {\n\n\n\n\n\n\n\n\n\n\n\n\n\n\n\n}\n")
            result = self.run_tool("--top", "4", "src", cwd=tmp)
            self.assertEqual(result.returncode, 0, result.stderr)
            self.assertEqual(result.stdout,
                             "   12  src/demo.cpp:15  twice\n"
                             "   11  src/demo.cpp:44  Widget::helper\n"
                             "    9  src/more.hpp:10  Traits::operator()\n"
                             "    5  src/demo.cpp:30  Widget::Widget\n")
            self.assertEqual(result.stderr, "")
            # A file named alone, and the default of ten.
            result = self.run_tool(os.path.join("src", "more.hpp"), cwd=tmp)
            self.assertEqual(len(result.stdout.splitlines()), len(EXPECTED_MORE))
            self.assertTrue(result.stdout.startswith("    9  src/more.hpp:10  Traits::operator()\n"))

    def test_bad_arguments_are_refused(self):
        for args, message in [(["--top", "0"], "'0' is not a whole number of at least 1"),
                              (["--top", "x"], "'x' is not a whole number of at least 1"),
                              (["/no/such/dir"], "no such file or directory: /no/such/dir")]:
            result = self.run_tool(*args)
            self.assertEqual(result.returncode, 2, args)
            self.assertIn(message, result.stderr)
            self.assertEqual(result.stdout, "")

    def test_default_paths_are_the_library(self):
        result = self.run_tool("--top", "3", cwd=os.path.join(os.path.dirname(TOOL), "..", ".."))
        self.assertEqual(result.returncode, 0, result.stderr)
        lines = result.stdout.splitlines()
        self.assertEqual(len(lines), 3)
        lengths = [int(line.split()[0]) for line in lines]
        self.assertEqual(lengths, sorted(lengths, reverse=True))
        for line in lines:
            self.assertRegex(line, r"^ +\d+  raster/(include|src|tools)/\S+:\d+  \S")


if __name__ == "__main__":
    unittest.main()
