namespace PmacStream.Sim.Tests;
