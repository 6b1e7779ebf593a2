// "Did you mean ...?": the nearest known name to a mistyped one.
#pragma once

#include <algorithm>
#include <string>
#include <vector>

namespace mbd {

// Optimal-string-alignment distance (Levenshtein plus adjacent transpositions).
inline int edit_distance(const std::string& a, const std::string& b) {
    const size_t n = a.size(), m = b.size();
    std::vector<std::vector<int>> d(n + 1, std::vector<int>(m + 1, 0));
    for (size_t i = 0; i <= n; ++i) d[i][0] = static_cast<int>(i);
    for (size_t j = 0; j <= m; ++j) d[0][j] = static_cast<int>(j);
    for (size_t i = 1; i <= n; ++i) {
        for (size_t j = 1; j <= m; ++j) {
            const int cost = a[i - 1] == b[j - 1] ? 0 : 1;
            d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
                d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
        }
    }
    return d[n][m];
}

// The candidate nearest to `name`, or "" when none is close enough to be a typo.
inline std::string nearest_name(const std::string& name, const std::vector<std::string>& candidates) {
    std::string best;
    int best_distance = 1 << 30;
    for (const auto& candidate : candidates) {
        const int distance = edit_distance(name, candidate);
        if (distance < best_distance) {
            best_distance = distance;
            best = candidate;
        }
    }
    const int limit = std::max(2, static_cast<int>(std::max(name.size(), best.size())) / 2);
    return !best.empty() && best_distance <= limit ? best : std::string();
}

}  // namespace mbd
