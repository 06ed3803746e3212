#!/usr/bin/python3
"""Tests of scripts/long_functions.py on small source trees written here:
namespaces, class members, lambdas, constructors' braced initializers,
comments and literals with braces, and the --check allow-list."""
import os
import subprocess
import sys
import tempfile
import textwrap
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, "..", "long_functions.py")

SOURCE = textwrap.dedent("""\
    #include <vector>
    #define OPEN {
    namespace gp {
    namespace {
    struct Table { int a; int b; };
    const int kValues[] = {1, 2, 3};
    int helper(int x) {
      auto square = [](int y) {
        return y * y;
      };
      const char* brace = "}}}";  // a brace } in a comment
      /* and { here */
      char c = '}';
      return square(x) + 1'000;
    }
    }  // namespace

    class Solver {
     public:
      explicit Solver(int n) : n_{n}, data_(n) {
        for (int i = 0; i < n; ++i) data_[i] = i;
      }
      int size() const { return n_; }
      bool operator()(int k) const {
        return k < n_;
      }
     private:
      int n_;
      std::vector<int> data_;
    };

    enum class Kind { a, b };

    template <typename T>
    T Solver_twice(T x) {
      return x + x;
    }
    }  // namespace gp
    """)

EXPECTED = {
    ("helper", 7, 9),
    ("Solver::Solver", 20, 3),
    ("Solver::size", 23, 1),
    ("Solver::operator()", 24, 3),
    ("Solver_twice", 35, 3),
}


def run(root, *args):
    r = subprocess.run([sys.executable, SCRIPT, "--root", root, *args], capture_output=True, text=True)
    return r.returncode, r.stdout, r.stderr


class LongFunctionsTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.root = self.tmp.name
        os.makedirs(os.path.join(self.root, "common", "room", "tests"))
        with open(os.path.join(self.root, "common", "room", "solver.cpp"), "w") as f:
            f.write(SOURCE)
        # A test's function is not the library's: it must not be listed.
        with open(os.path.join(self.root, "common", "room", "tests", "solver_test.cpp"), "w") as f:
            f.write("void long_test() {\n" + "  int x = 0;\n" * 200 + "}\n")

    def tearDown(self):
        self.tmp.cleanup()

    def listed(self, stdout):
        found = set()
        for line in stdout.splitlines():
            where, name, length = line.split(" ", 2)
            self.assertTrue(where.startswith("common/room/solver.cpp:"), line)
            found.add((name, int(where.split(":")[1]), int(length.split()[0].strip("("))))
        return found

    def test_every_function_with_its_line_and_length(self):
        code, out, _ = run(self.root, "--max", "0")
        self.assertEqual(code, 0)
        self.assertEqual(self.listed(out), EXPECTED)

    def test_limit(self):
        code, out, _ = run(self.root, "--max", "5")
        self.assertEqual(code, 0)
        self.assertEqual(self.listed(out), {("helper", 7, 9)})

    def test_check_fails_on_a_long_function_and_the_allow_list_lets_it_pass(self):
        allow = os.path.join(self.root, "allowed.txt")
        code, out, err = run(self.root, "--max", "5", "--check", "--allow", allow)
        self.assertEqual(code, 1)
        self.assertIn("NEW", out)
        with open(allow, "w") as f:
            f.write("# comment\ncommon/room/solver.cpp helper  # a reason\n")
        code, out, err = run(self.root, "--max", "5", "--check", "--allow", allow)
        self.assertEqual(code, 0, out + err)
        self.assertIn("allowed: a reason", out)
        # Under a larger limit the entry is stale: said, not failed.
        code, out, err = run(self.root, "--max", "50", "--check", "--allow", allow)
        self.assertEqual(code, 0)
        self.assertIn("no longer over 50 lines", out)

    def test_an_entry_without_a_reason_is_an_error(self):
        allow = os.path.join(self.root, "allowed.txt")
        with open(allow, "w") as f:
            f.write("common/room/solver.cpp helper\n")
        code, _, err = run(self.root, "--max", "5", "--check", "--allow", allow)
        self.assertEqual(code, 2)
        self.assertIn("allowed.txt:1", err)


if __name__ == "__main__":
    unittest.main()
