#pragma once
// Small text helpers shared by the CSV readers and writers.

#include <string>
#include <string_view>
#include <vector>

namespace aar {

/// Removes a trailing '\r' (files written on Windows).
std::string TrimCr(std::string_view line);

/// Splits on ',' (no quoting: the project's CSV files hold numbers and labels only).
std::vector<std::string> SplitCsvLine(std::string_view line);

/// Parses a finite double that spans the whole field; throws aar::Error
/// "<where>: '<text>' is not a finite number" otherwise.
double ParseFiniteDouble(std::string_view text, const std::string& where);

/// Parses a non-negative integer that spans the whole field.
long long ParseInteger(std::string_view text, const std::string& where);

/// `text` with every byte outside printable ASCII written as \xHH, for
/// messages that quote file content.
std::string PrintableText(std::string_view text);

/// Fixed-point formatting independent of the locale, "-0" printed as "0";
/// beyond 10^15 in magnitude the shortest form ("1e+300").
std::string FormatFixed(double value, int decimals);

}  // namespace aar
