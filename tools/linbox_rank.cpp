// Rank of a sparse integer matrix with LinBox, timed, for tools/linbox_compare.py.
//
//     apt-get install -y liblinbox-dev libntl-dev libiml-dev libflint-dev
//     g++ -O2 -std=c++17 tools/linbox_rank.cpp -o /tmp/linbox_rank $(pkg-config --cflags --libs linbox)
//     /tmp/linbox_rank FILE
//
// (pkg-config's flags for linbox link NTL, IML and FLINT, whose headers LinBox's headers
// include; liblinbox-dev 1.7.0-3 does not depend on their -dev packages.)
//
// FILE is what `export_system N FILE` writes: a line `rows cols`, then one line per row of
// `col:value` pairs separated by spaces (0-based columns, integer values of at most 64 bits).
//
// Two ranks of the same `SparseMatrix<Field, SparseMatrixFormat::SparseSeq>`, both computed by
// LinBox's sparse Gaussian elimination (GaussDomain::InPlaceLinearPivoting, reached through
// PivotStrategy::Linear: at each step the sparsest remaining row, found by scanning them all,
// then in it the column with the fewest entries; the pivot row is then eliminated from every
// remaining row, so each step visits all rows below it):
//   * modulo the prime 2^31 - 1, over Givaro::Modular<uint32_t, uint64_t>:
//     `rank(r, A, Method::SparseElimination())`;
//   * over Givaro::ZRing<Givaro::Integer>: `rank(r, A)`, the default Method::Auto (naming
//     Method::SparseElimination for an integer matrix does not compile in LinBox 1.7: the
//     call is ambiguous). LinBox does not eliminate over Z: for the IntegerTag it maps the
//     matrix modulo one random prime (Givaro::ModularBalanced<double>; 23 bits for 256 rows
//     or more; see integral_rank in linbox/solutions/rank.inl) and, Auto on a SparseSeq
//     matrix meaning Elimination and then SparseElimination, eliminates there. That is a
//     Monte Carlo answer: a lower bound of the rank r over Z, equal to it unless the prime
//     divides every r × r minor.
// The rank call copies (or reduces) the input matrix itself, since elimination destroys it;
// that copy is timed, reading the file and building the input matrix are not. Each rank is
// timed with std::chrono: best of 3 runs, or of fewer when a run takes over 10 s.
//
// Standard output:
//     rows ROWS cols COLS nnz NNZ
//     rank_mod_p R time_ms T prime 2147483647 runs K
//     rank_int R time_ms T runs K

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <givaro/modular.h>
#include <givaro/zring.h>
#include <linbox/matrix/sparse-matrix.h>
#include <linbox/solutions/rank.h>

namespace {

struct Entry {
    std::size_t row;
    std::size_t col;
    long long value;
};

struct Triplets {
    std::size_t rows = 0;
    std::size_t cols = 0;
    std::vector<Entry> entries;
};

// Parses an unsigned or signed decimal at `p`, advancing `p`; throws on overflow or no digits.
long long parse_integer(const char*& p, const std::string& what) {
    char* end = nullptr;
    errno = 0;
    const long long v = std::strtoll(p, &end, 10);
    if (end == p || errno == ERANGE)
        throw std::runtime_error("bad or too large " + what);
    p = end;
    return v;
}

Triplets read_matrix(const char* path) {
    std::ifstream in(path);
    if (!in)
        throw std::runtime_error(std::string("cannot open ") + path);
    Triplets t;
    std::string line;
    if (!std::getline(in, line) || !(std::istringstream(line) >> t.rows >> t.cols))
        throw std::runtime_error("first line must be `rows cols`");
    for (std::size_t i = 0; i < t.rows; ++i) {
        if (!std::getline(in, line))
            throw std::runtime_error("fewer row lines than announced");
        const char* p = line.c_str();
        while (true) {
            while (*p == ' ')
                ++p;
            if (*p == '\0')
                break;
            const long long col = parse_integer(p, "column");
            if (*p++ != ':' || col < 0 || static_cast<std::size_t>(col) >= t.cols)
                throw std::runtime_error("bad entry in row " + std::to_string(i));
            t.entries.push_back({i, static_cast<std::size_t>(col), parse_integer(p, "value")});
        }
    }
    return t;
}

template <class Field>
LinBox::SparseMatrix<Field, LinBox::SparseMatrixFormat::SparseSeq>
to_sparse(const Field& F, const Triplets& t) {
    LinBox::SparseMatrix<Field, LinBox::SparseMatrixFormat::SparseSeq> A(F, t.rows, t.cols);
    typename Field::Element e;
    for (const Entry& x : t.entries) {
        // From int64_t, not Givaro::Integer: Givaro 4.2's Modular<uint32_t>::init from a
        // negative Integer wraps around 2^32 instead of reducing modulo p.
        F.init(e, static_cast<int64_t>(x.value));
        if (!F.isZero(e))
            A.setEntry(x.row, x.col, e);
    }
    return A;
}

struct Timed {
    std::size_t rank;
    double best_ms;
    int runs;
};

// `rank(r, A, method)`: best of 3 runs, stopping early after a run over 10 s.
template <class Matrix, class Method>
Timed time_rank(const Matrix& A, const Method& method) {
    Timed out{0, 0.0, 0};
    double best = 1e300;
    for (out.runs = 1; out.runs <= 3; ++out.runs) {
        std::size_t r = 0;
        const auto start = std::chrono::steady_clock::now();
        LinBox::rank(r, A, method);
        const std::chrono::duration<double, std::milli> ms =
            std::chrono::steady_clock::now() - start;
        if (out.runs > 1 && r != out.rank)
            throw std::runtime_error("rank differs between runs");
        out.rank = r;
        best = std::min(best, ms.count());
        if (ms.count() > 10000.0 || out.runs == 3)
            break;
    }
    out.best_ms = best;
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::cerr << "usage: linbox_rank FILE\n";
        return 2;
    }
    try {
        const Triplets t = read_matrix(argv[1]);
        std::printf("rows %zu cols %zu nnz %zu\n", t.rows, t.cols, t.entries.size());
        std::fflush(stdout);

        const uint32_t prime = 2147483647u;  // 2^31 - 1
        const Givaro::Modular<uint32_t, uint64_t> Fp(prime);
        const Timed mod_p = time_rank(to_sparse(Fp, t), LinBox::Method::SparseElimination());
        std::printf("rank_mod_p %zu time_ms %.3f prime %u runs %d\n", mod_p.rank, mod_p.best_ms,
                    prime, mod_p.runs);
        std::fflush(stdout);

        const Givaro::ZRing<Givaro::Integer> Z;
        const Timed over_z = time_rank(to_sparse(Z, t), LinBox::Method::Auto());
        std::printf("rank_int %zu time_ms %.3f runs %d\n", over_z.rank, over_z.best_ms,
                    over_z.runs);
    } catch (const std::exception& e) {
        std::cerr << "error: " << e.what() << '\n';
        return 1;
    }
    return 0;
}
