// Linked with one of the analyzer's layer libraries whole (every object) and
// the layers below it only (analyzer/CMakeLists.txt): an object that calls
// into a higher layer leaves an undefined symbol, and this fails to link.
int main() { return 0; }
