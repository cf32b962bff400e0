// atomic_file: being written.
