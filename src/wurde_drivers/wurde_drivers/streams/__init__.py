"""The stream contract shared by the dummies and the real drivers: which WURDE streams a base, a
laser, a DMU and a GPS publish, under which names and with which standard-message mirrors.  A dummy
and a driver that publish through the same class here are interchangeable by configuration alone."""
