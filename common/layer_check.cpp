// Linked with one layer library whole (every object) and the layers below it
// only (analyzer/CMakeLists.txt, renderer/CMakeLists.txt): an object that
// calls into a higher layer leaves an undefined symbol, and this fails to link.
int main() { return 0; }
