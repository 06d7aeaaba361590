#pragma once
// Boost.Asio for the network consumers. Boost 1.74's awaitable.hpp uses std::exchange without
// including <utility>, which C++20 libstdc++ no longer pulls in on the way: include it first.
// clang-format off
#include <utility>
#include <boost/asio.hpp>
// clang-format on
