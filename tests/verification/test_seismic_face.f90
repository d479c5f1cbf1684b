!> Verification: a base shaken by a record (domain.boundaries.<face>.type = "seismic").
!>
!> A laterally confined elastic column (sliding sides, 2D plane strain, 2 cells wide) 3 m
!> high, E = 1 MPa, nu = 0.3, rho = 1000 (P-wave speed vp = sqrt(M / rho) = 36.69 m/s), no
!> gravity, free top, at rest. Its base moves up with the velocity pulse
!> v(t) = v0 sin^2(pi t / T), v0 = 0.05 m/s, T = 0.8 m / vp (a pulse 0.8 m = 16 cells long),
!> given as a velocity record or as its acceleration record (pi v0 / T sin(2 pi t / T)).
!> The pulse runs up the column (H / vp = 0.082 s) and reflects at the free top, where the
!> velocity doubles (d'Alembert).
!>
!> - Rigid base: the top's largest velocity is 2 v0 within 3 % (0.2 % measured: the wave
!>   arrives whole, the grid's dispersion spreads it a little), reached at H / vp + T / 2
!>   within 5 % of H / vp (the grid's waves are a little slower); the acceleration record
!>   gives the same motion to 1e-3 of v0 (the velocity record is exact at its rows, the
!>   integral of the acceleration one between them too); the momentum of the particles is the
!>   base's impulse (the time integral of the reaction in history.csv) to 1e-9 of it, in both
!>   components; the energy residual stays below 2 % of the base's work (load_work), with
!>   FLIP and with APIC (whose balance books the nodes' kinetic energies).
!> - Compliant base (vp, vs of the column itself, Joyner and Chen 1975): the record is the
!>   outcrop motion, twice the incident wave, so the top's largest velocity is v0 within 3 %;
!>   the wave that comes back down leaves through the base: at 0.22 s less than 1 % of the
!>   energy the base brought in is left in the column, and the residual is below 2 % of it.
!> - The face's reading: the summary, the record's velocity between the rows (exact for both
!>   kinds), and the refusals of a record the face cannot use.
program test_seismic_face
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, finish
    use mpm_error, only: error_type
    use mpm_strings, only: fmt_real
    use mpm_case, only: case_type, read_case_string, case_summary
    use mpm_solver, only: simulation_type, new_simulation, advance, stable_time_step, &
        start_energy_balance, energy_residual
    implicit none

    real(wp), parameter :: young = 1.0e6_wp, nu = 0.3_wp, rho = 1000.0_wp, v0 = 0.05_wp
    real(wp), parameter :: height = 3.0_wp, pi = acos(-1.0_wp)
    character(len=*), parameter :: velocity_file = "test_seismic_velocity.csv", &
        acceleration_file = "test_seismic_acceleration.csv"
    type(test_suite_type) :: suite
    real(wp) :: modulus, vp, vs, period, peak, at, peak_a, at_a, most_apart, left, given, &
        residual, momentum(2), impulse(2)

    call new_suite(suite, "seismic_face")
    modulus = young*(1 - nu)/((1 + nu)*(1 - 2*nu))
    vp = sqrt(modulus/rho)
    vs = sqrt(young/(2*(1 + nu))/rho)
    period = 1.6_wp/vp
    call write_records()
    call check_reading()

    call run_column('"record": "velocity", "file": "'//velocity_file//'"', 0.15_wp, peak, at, &
        left, given, residual, momentum, impulse)
    print "(a, 4(a, es11.4))", "rigid base, velocity record", ": top's largest v / 2 v0 ", &
        peak/(2*v0), ", at ", at, " s (H / vp + T / 2 = ", height/vp + period/2, &
        "), residual / base's work ", residual/given
    call check_close(suite, peak, 2*v0, 0.03_wp*2*v0, "rigid base: the top moves at 2 v0 (3 %)")
    call check_close(suite, at, height/vp + period/2, 0.05_wp*height/vp, &
        "rigid base: the pulse reaches the top at H / vp + T / 2 (5 % of H / vp)")
    call check(suite, all(abs(momentum - impulse) <= 1.0e-9_wp*maxval(abs(impulse))) .and. &
        impulse(2) > 0.0_wp, "rigid base: the particles' momentum is the base's impulse")
    call check(suite, given > 0.0_wp .and. abs(residual) < 0.02_wp*given, &
        "rigid base: the base's work is booked (residual below 2 % of it)")
    call run_column('"record": "acceleration", "file": "'//acceleration_file//'"', 0.15_wp, &
        peak_a, at_a, left, given, residual, momentum, impulse, most_apart)
    print "(a, 2(a, es11.4))", "rigid base, acceleration record", ": top's largest v / 2 v0 ", &
        peak_a/(2*v0), ", largest difference from the velocity record / v0 ", most_apart/v0
    call check(suite, most_apart < 1.0e-3_wp*v0, &
        "rigid base: the acceleration record moves the column as the velocity record")

    ! APIC: the nodes' kinetic energies are booked (a velocity face's held nodes are not
    ! stopped: booked as stopped, the mapped kinetic energy made the residual 66 % of the work)
    call run_column('"record": "velocity", "file": "'//velocity_file//'"', 0.15_wp, peak, at, &
        left, given, residual, momentum, impulse, transfer="apic")
    print "(a, 2(a, es11.4))", "rigid base, APIC", ": top's largest v / 2 v0 ", peak/(2*v0), &
        ", residual / base's work ", residual/given
    call check(suite, given > 0.0_wp .and. abs(residual) < 0.02_wp*given, &
        "rigid base, APIC: the base's work is booked (residual below 2 % of it)")

    call run_column('"record": "velocity", "file": "'//velocity_file//'", "vp": ' &
        //fmt_real(vp, 15)//', "vs": '//fmt_real(vs, 15), 0.25_wp, peak, at, left, given, &
        residual, momentum, impulse)
    print "(a, 4(a, es11.4))", "compliant base", ": top's largest v / v0 ", peak/v0, ", at ", &
        at, " s, energy left / brought in ", left/given, ", residual / brought in ", &
        residual/given
    call check_close(suite, peak, v0, 0.03_wp*v0, &
        "compliant base: the top moves at the outcrop velocity v0 (3 %)")
    call check(suite, given > 0.0_wp .and. left < 0.01_wp*given, &
        "compliant base: the wave leaves through the base (below 1 % left)")
    call check(suite, abs(residual) < 0.02_wp*given, &
        "compliant base: residual below 2 % of what the base brought in")
    call remove_records()
    call finish(suite)

contains

    !> The record files are the test's own: removed at the end.
    subroutine remove_records()
        integer :: unit

        open (newunit=unit, file=velocity_file, status="old")
        close (unit, status="delete")
        open (newunit=unit, file=acceleration_file, status="old")
        close (unit, status="delete")
    end subroutine remove_records

    !> The pulse as a velocity record and as an acceleration record, 200 rows over 2 T.
    subroutine write_records()
        integer :: unit, k
        real(wp) :: t

        open (newunit=unit, file=velocity_file, status="replace", action="write")
        write (unit, "(a)") "time, velocity"
        do k = 0, 200
            t = k*period/100
            write (unit, "(es24.16, ', ', es24.16)") t, merge(v0*sin(pi*t/period)**2, 0.0_wp, &
                t <= period)
        end do
        close (unit)
        open (newunit=unit, file=acceleration_file, status="replace", action="write")
        write (unit, "(a)") "time, acceleration"
        do k = 0, 200
            t = k*period/100
            write (unit, "(es24.16, ', ', es24.16)") t, merge(pi*v0/period &
                *sin(2*pi*t/period), 0.0_wp, t <= period)
        end do
        close (unit)
    end subroutine write_records

    !> The case of the column on a seismic base with the given keys.
    function column_case(keys, transfer) result(text)
        character(len=*), intent(in) :: keys
            !! the face object's keys besides type and scale
        character(len=*), intent(in), optional :: transfer
            !! solver.transfer (default flip)
        character(len=:), allocatable :: text

        character(len=8) :: name

        name = "flip"
        if (present(transfer)) name = transfer

        text = '{"name": "shaken", "domain": {"nx": 2, "ny": 60, "dx": 0.05, ' &
            //'"boundaries": {"xmin": "sliding", "xmax": "sliding", "ymin": {"type": ' &
            //'"seismic", "scale": [0, 1], '//keys//'}}}, "particles": {"ppc": 2}, ' &
            //'"materials": [{"name": "m", "type": "linear_elastic", "E": 1e6, "nu": 0.3, ' &
            //'"rho": 1000}], "bodies": [{"material": "m", "min": [0, 0], "max": [0.1, 3.0]}], ' &
            //'"gravity": [0, 0], "solver": {"scheme": "MUSL", "shape_function": "cpgimp", ' &
            //'"transfer": "'//trim(name)//'"}, "time": {"tend": 1, "cfl": 0.5}}'
    end function column_case

    !> The column on the base given by `keys`, to t = tend: the largest mean vertical
    !> velocity of the top particles and when, the kinetic + elastic energy at the end, the
    !> base's work, the energy residual, the particles' momentum and the base's impulse; with
    !> `apart`, the largest difference of the top's velocity from the velocity record's run
    !> (kept in `history`, filled by that run).
    subroutine run_column(keys, tend, peak, at, left, given, residual, momentum, impulse, apart, &
        transfer)
        character(len=*), intent(in) :: keys
            !! the face object's keys besides type and scale
        real(wp), intent(in) :: tend
            !! end of the run [s]
        real(wp), intent(out) :: peak, at, left, given, residual, momentum(2), impulse(2)
            !! see above
        real(wp), intent(out), optional :: apart
            !! largest difference from the first run's top velocity [m/s]
        character(len=*), intent(in), optional :: transfer
            !! solver.transfer (default flip; not with apart)

        real(wp), allocatable, save :: history(:)
        type(case_type) :: case
        type(simulation_type) :: sim
        type(error_type), allocatable :: error
        real(wp) :: dt, v, top
        integer :: step, p
        logical, allocatable :: upper(:)

        peak = 0.0_wp
        at = 0.0_wp
        left = huge(1.0_wp)
        given = 0.0_wp
        residual = huge(1.0_wp)
        momentum = 0.0_wp
        impulse = huge(1.0_wp)
        if (present(apart)) apart = huge(1.0_wp)
        call read_case_string(column_case(keys, transfer), case, error, "shaken")
        if (.not. allocated(error)) call new_simulation(sim, case, error)
        call check(suite, .not. allocated(error), keys//": set-up")
        if (allocated(error)) then
            print "(a)", error%message
            return
        end if
        call start_energy_balance(sim)
        top = maxval(sim%particles%x(2, 1:sim%particles%n))
        upper = sim%particles%x(2, 1:sim%particles%n) > top - 1.0e-9_wp
        if (present(apart)) then
            apart = 0.0_wp
        else if (.not. present(transfer)) then
            if (allocated(history)) deallocate (history)
            allocate (history(0))
        end if
        impulse = 0.0_wp
        step = 0
        ! a fixed step, the same in every run: the runs compare step by step
        dt = 0.5_wp*stable_time_step(sim)
        do while (sim%time < tend - 0.5_wp*dt)
            call advance(sim, dt, error)
            if (allocated(error)) then
                call check(suite, .false., keys//": run failed: "//error%message)
                return
            end if
            step = step + 1
            impulse = impulse + dt*sim%face_reaction(1:2, 1, 2)
            v = sum(sim%particles%v(2, 1:sim%particles%n), mask=upper)/count(upper)
            if (v > peak) then
                peak = v
                at = sim%time
            end if
            if (present(apart)) then
                if (step <= size(history)) apart = max(apart, abs(v - history(step)))
            else if (.not. present(transfer)) then
                history = [history, v]
            end if
        end do
        do p = 1, 2
            momentum(p) = sum(sim%particles%mass(1:sim%particles%n) &
                *sim%particles%v(p, 1:sim%particles%n))
        end do
        left = sim%energy%kinetic + sim%energy%elastic
        given = sim%energy%loads
        residual = energy_residual(sim%energy)
    end subroutine run_column

    !> The face as the case gives it: the summary, the record's velocity between the rows,
    !> and what is refused.
    subroutine check_reading()
        type(case_type) :: case
        type(error_type), allocatable :: error
        real(wp) :: v(3), t

        call read_case_string(column_case('"record": "acceleration", "file": "' &
            //acceleration_file//'"'), case, error, "shaken")
        call check(suite, .not. allocated(error), "acceleration record: valid")
        if (allocated(error)) then
            print "(a)", error%message
            return
        end if
        call check(suite, index(case_summary(case), 'ymin seismic (acceleration record "' &
            //acceleration_file//'", 201 rows') > 0 .and. index(case_summary(case), &
            "rigid base)") > 0, "acceleration record: summary")
        ! the velocity between the rows: the pulse's, to the error of its linear pieces
        t = 0.2537_wp*period
        v = case%domain%face(1, 2)%b%velocity_at(t, 2)
        call check_close(suite, v(2), v0*sin(pi*t/period)**2, 2.0e-4_wp*v0, &
            "acceleration record: integrated from rest between the rows")
        call check(suite, v(1) == 0.0_wp, "acceleration record: along scale only")
        v = case%domain%face(1, 2)%b%velocity_at(3*period, 2)
        call check_close(suite, v(2), 0.0_wp, 1.0e-12_wp, &
            "acceleration record: the velocity after the record is the record's last")
        call expect_refusal('"record": "speed", "file": "'//velocity_file//'"', &
            'domain.boundaries.ymin.record = "speed" is not allowed', "record kind")
        call expect_refusal('"record": "velocity", "file": "test_seismic_no_such.csv"', &
            'domain.boundaries.ymin.file = "test_seismic_no_such.csv": no such file', &
            "missing file")
        call expect_refusal('"record": "velocity"', &
            "missing required key 'domain.boundaries.ymin.file'", "no file")
        call expect_refusal('"record": "velocity", "file": "'//velocity_file//'", "vs": 10', &
            "domain.boundaries.ymin gives vs without vp", "vs alone")
        call expect_refusal('"record": "velocity", "file": "'//velocity_file//'", "vp": 10, ' &
            //'"vs": 10', "domain.boundaries.ymin.vs = 10 m/s is not below sqrt(3)/2 vp", &
            "vs too large")
        call expect_refusal('"record": "velocity", "file": "'//velocity_file//'", "mu": 0.3', &
            "domain.boundaries.ymin.mu applies to frictional faces only", "mu")
    end subroutine check_reading

    !> The column with these keys is refused with a message holding `text`.
    subroutine expect_refusal(keys, text, label)
        character(len=*), intent(in) :: keys, text, label
        type(case_type) :: case
        type(error_type), allocatable :: error

        call read_case_string(column_case(keys), case, error, "shaken")
        call check(suite, allocated(error), "refused: "//label)
        if (.not. allocated(error)) return
        call check(suite, index(error%message, text) > 0, "message: "//label)
        if (index(error%message, text) == 0) print "(a)", "  got: "//error%message
    end subroutine expect_refusal

end program test_seismic_face
