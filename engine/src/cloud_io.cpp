// cloud_io: being written.
