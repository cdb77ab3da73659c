using PmacStream.Plc;
using PmacStream.Pmac;
using PmacStream.Sim;

namespace PmacStream.Testing;

/// <summary>
/// Something that runs a generated PLC program: the test sets the physical input word, runs scans and reads the
/// physical output word, like a hand on the terminal block.
/// </summary>
public interface IPlcRig
{
    /// <summary>Sets the physical inputs word (bits as wired).</summary>
    void SetInputs(long word);

    /// <summary>Runs one PLC scan.</summary>
    void Scan();

    /// <summary>Reads the physical outputs word.</summary>
    long Outputs { get; }

    /// <summary>Captures everything the program keeps between scans (I/O words and images).</summary>
    object Snapshot();

    /// <summary>Puts a captured state back.</summary>
    void Restore(object snapshot);

    /// <summary>Clears the I/O words and images, as at power-up (open memory is zeroed).</summary>
    void PowerUp();
}

/// <summary>
/// Runs the generated lines in the generator's own evaluator (<c>PlcEvaluator</c>, internal to PmacStream.Plc, which
/// opens it to the kit), independent of the simulator: the second engine the same explorer runs on.
/// </summary>
public sealed class EvaluatorRig : IPlcRig
{
    private readonly PlcEvaluator _ev;
    private readonly IoWordConfig _in;
    private readonly IoWordConfig _out;
    private readonly int[] _stateWords;

    public EvaluatorRig(LadderProgram program, GeneratedPlc generated)
    {
        _ev = PlcEvaluator.Load(generated.DownloadLines);
        _in = program.Inputs;
        _out = program.Outputs;
        _stateWords = [program.Inputs.ImageAddress, program.Outputs.ImageAddress, program.Internals.Address, program.Internals.Address + 1];
    }

    public void SetInputs(long word)
    {
        var mask = ((1L << _in.Width) - 1) << _in.Offset;
        var w = _ev.ReadWord(_in.Memory, _in.WordAddress);
        _ev.WriteWord(_in.Memory, _in.WordAddress, (w & ~mask) | ((word << _in.Offset) & mask));
    }

    public void Scan() => _ev.Scan();

    public long Outputs => (_ev.ReadWord(_out.Memory, _out.WordAddress) >> _out.Offset) & ((1L << _out.Width) - 1);

    public object Snapshot() =>
        (_ev.ReadWord(_in.Memory, _in.WordAddress), _ev.ReadWord(_out.Memory, _out.WordAddress), _stateWords.Select(a => _ev.ReadWord('Y', a)).ToArray());

    public void PowerUp() => Restore(((long)0, (long)0, new long[_stateWords.Length]));

    public void Restore(object snapshot)
    {
        var (i, o, words) = ((long, long, long[]))snapshot;
        _ev.WriteWord(_in.Memory, _in.WordAddress, i);
        _ev.WriteWord(_out.Memory, _out.WordAddress, o);
        for (var k = 0; k < words.Length; k++)
        {
            _ev.WriteWord('Y', _stateWords[k], words[k]);
        }
    }
}

/// <summary>
/// Runs a generated program in the simulated Turbo PMAC: downloaded over the host protocol (InProcessConnection on a
/// simulator port), inputs set on the simulated I/O word, one deterministic scan per step, outputs read back.
/// </summary>
public sealed class SimulatorRig : IPlcRig, IDisposable
{
    private readonly IoWordConfig _in;
    private readonly IoWordConfig _out;
    private readonly int[] _stateWords;

    private SimulatorRig(SimHarness harness, LadderProgram program)
    {
        Harness = harness;
        _in = program.Inputs;
        _out = program.Outputs;
        _stateWords = [program.Inputs.ImageAddress, program.Outputs.ImageAddress, program.Internals.Address, program.Internals.Address + 1];
    }

    /// <summary>The kit's rig, bottom layer: the simulator and the host's port on it.</summary>
    public SimHarness Harness { get; }

    public PmacSimulator Simulator => Harness.Sim;

    public IPmacConnection Connection { get; private set; } = null!;

    public static async Task<SimulatorRig> CreateAsync(LadderProgram program, GeneratedPlc generated)
    {
        var rig = new SimulatorRig(new SimHarness(port: "host"), program);
        rig.Connection = new InProcessConnection(rig.Harness.Port, "sim");
        await rig.Connection.DownloadAsync(generated.DownloadLines);
        return rig;
    }

    public void SetInputs(long word)
    {
        var mask = ((1L << _in.Width) - 1) << _in.Offset;
        var w = (long)Simulator.GetWord(_in.Memory, _in.WordAddress);
        Simulator.SetWord(_in.Memory, _in.WordAddress, (int)((w & ~mask) | ((word << _in.Offset) & mask)));
    }

    public void Scan() => Simulator.RunPlcScan();

    public long Outputs => (Simulator.GetWord(_out.Memory, _out.WordAddress) >> _out.Offset) & ((1L << _out.Width) - 1);

    public object Snapshot() =>
        (Simulator.GetWord(_in.Memory, _in.WordAddress), Simulator.GetWord(_out.Memory, _out.WordAddress), _stateWords.Select(a => Simulator.GetWord('Y', a)).ToArray());

    public void Restore(object snapshot)
    {
        var (i, o, words) = ((int, int, int[]))snapshot;
        Simulator.SetWord(_in.Memory, _in.WordAddress, i);
        Simulator.SetWord(_out.Memory, _out.WordAddress, o);
        for (var k = 0; k < words.Length; k++)
        {
            Simulator.SetWord('Y', _stateWords[k], words[k]);
        }
    }

    public void PowerUp() => Restore((0, 0, new int[_stateWords.Length]));

    public void Dispose() => Harness.Dispose();
}
