// Placeholder replaced by the benchmark program (see scripts/bench-search).
int main() { return 0; }
