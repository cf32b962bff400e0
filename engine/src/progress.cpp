// progress: being written.
