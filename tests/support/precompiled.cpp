// Nothing of its own: the target this unit belongs to builds the tests' precompiled header,
// which every test executable reuses (cmake/PrecompiledHeaders.cmake).
