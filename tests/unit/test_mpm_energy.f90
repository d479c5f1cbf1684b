!> Unit tests of the energy balance's bookkeeping (mpm_energy): how step_energies books the
!> sums of a step into the terms, the total and residual, the guard's scale and the record
!> of a checkpoint. The values are sums of powers of two, so every sum is exact and the
!> checks compare exactly.
program test_mpm_energy
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, finish
    use mpm_material, only: nwork_kinds, work_stored, work_plastic, work_viscous
    use mpm_kernel_stress, only: nstress_sums
    use mpm_kernel_nodal, only: nnodal_sums, nodal_damping, nodal_friction, nodal_boundary, &
        nodal_faces, nodal_absorbed, nodal_rigid
    use mpm_energy, only: energies_type, energy_total, energy_residual, energy_scale, &
        energy_record, energies_from_record, nenergy_record, step_energies
    implicit none

    integer, parameter :: nsums = 6 + nstress_sums + nnodal_sums
        !! the sums of a step as mpm_solver::advance gives them
    type(test_suite_type) :: suite

    call new_suite(suite, "mpm_energy")
    call test_booking()
    call test_transfer()
    call test_closed_step()
    call test_record_and_scale()
    call finish(suite)

contains

    !> The sums of a step: kinetic energy after it, change of the potential, work of the
    !> body forces, the work and stored energy by kind, the nodal sums, the nodes' kinetic
    !> energies after P2G and after the nodal update, the blend's loss.
    pure function step_sums(kinetic, potential, loads, work, stored, nodal, grid, blend) &
            result(sums)
        real(wp), intent(in) :: kinetic, potential, loads, work(nwork_kinds), &
            stored(nwork_kinds), nodal(nnodal_sums), grid(2), blend
        real(wp) :: sums(nsums)

        sums = [kinetic, potential, loads, work, stored, nodal, grid, blend]
    end function step_sums

    !> A terms record before a step.
    pure function start_terms() result(e)
        type(energies_type) :: e

        e%kinetic = 8.0_wp
        e%initial = 8.0_wp
        e%potential = -2.0_wp
        e%plastic = 0.5_wp
        e%supplied = 2.0_wp
        e%stored = [0.25_wp, 0.125_wp, 0.0625_wp]
        e%elastic = sum(e%stored)
        e%damping = 0.25_wp
        e%friction = 0.5_wp
        e%boundary = 0.125_wp
        e%transfer = 0.25_wp
    end function start_terms

    !> Each sum goes to its term.
    subroutine test_booking()
        type(energies_type) :: before, e
        real(wp) :: work(nwork_kinds), stored(nwork_kinds), nodal(nnodal_sums)

        before = start_terms()
        work = 0.0_wp
        work(work_stored) = 0.5_wp
        work(work_plastic) = 1.0_wp
        work(work_viscous) = 0.25_wp
        stored = [0.75_wp, 0.375_wp, 0.125_wp]
        nodal = 0.0_wp
        nodal(nodal_damping) = 0.125_wp
        nodal(nodal_friction) = 0.25_wp
        nodal(nodal_boundary) = 0.0625_wp
        nodal(nodal_faces) = 0.5_wp
        nodal(nodal_absorbed) = 0.03125_wp
        nodal(nodal_rigid) = 0.015625_wp
        e = step_energies(before, step_sums(6.0_wp, -1.0_wp, 0.25_wp, work, stored, nodal, &
            [0.0_wp, 0.0_wp], 0.0_wp), grid_velocities=.false.)
        call check(suite, e%kinetic == 6.0_wp, "kinetic energy: the sum after the step")
        call check(suite, e%potential == -3.0_wp, "potential: the step's change added")
        call check(suite, e%loads == 0.75_wp, "loads: body forces and velocity faces added")
        call check(suite, e%strain == 1.75_wp, "strain work: all kinds added")
        ! plastic: its work minus the change of the plastic materials' elastic energy
        call check(suite, e%plastic == 0.5_wp + 1.0_wp - (0.375_wp - 0.125_wp), &
            "plastic work: work - change of the stored energy of the plastic kind")
        call check(suite, e%viscous == 0.25_wp - (0.125_wp - 0.0625_wp), &
            "viscous work: work - change of the stored energy of the viscous kind")
        call check(suite, all(e%stored == stored) .and. e%elastic == sum(stored), &
            "elastic energy: the stored energies of the step")
        call check(suite, e%damping == 0.375_wp .and. e%friction == 0.75_wp .and. &
            e%boundary == 0.234375_wp, "damping, friction, boundary (with the absorbed energy " &
            //"and what the rigid bodies' constraint took): " &
            //"the nodal sums added")
        call check(suite, e%supplied == 3.75_wp, "supplied: |potential| + |loads| when larger")
        call check(suite, e%initial == before%initial, "the start is kept")
        call check(suite, e%transfer == before%transfer, "FLIP: no transfer term")
        e = step_energies(e, step_sums(6.0_wp, 2.5_wp, 0.0_wp, [0.0_wp, 0.0_wp, 0.0_wp], &
            stored, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], [0.0_wp, 0.0_wp], 0.0_wp), &
            grid_velocities=.false.)
        call check(suite, e%supplied == 3.75_wp, "supplied: the largest so far is kept")
    end subroutine test_booking

    !> The transfer term: the nodes' kinetic energies for APIC and PIC, the blend's loss
    !> for FLIP.
    subroutine test_transfer()
        type(energies_type) :: before, e
        real(wp) :: zero(nwork_kinds), none(nnodal_sums)

        before = start_terms()
        zero = 0.0_wp
        none = 0.0_wp
        ! P2G gives the nodes 7 of the particles' 8 J, G2P gives the particles 5 of the
        ! nodes' 6 J: 2 J lost
        e = step_energies(before, step_sums(5.0_wp, 0.0_wp, 0.0_wp, zero, before%stored, none, &
            [7.0_wp, 6.0_wp], 0.0_wp), grid_velocities=.true.)
        call check(suite, e%transfer == before%transfer + 2.0_wp, &
            "APIC, PIC: (particles - nodes after P2G) + (nodes after the update - particles)")
        e = step_energies(before, step_sums(5.0_wp, 0.0_wp, 0.0_wp, zero, before%stored, none, &
            [7.0_wp, 6.0_wp], 0.5_wp), grid_velocities=.false.)
        call check(suite, e%transfer == before%transfer + 0.5_wp, &
            "FLIP-PIC blend: its loss, not the nodes' kinetic energies")
    end subroutine test_transfer

    !> A step whose sums are those of an exact exchange leaves the residual as it was.
    subroutine test_closed_step()
        type(energies_type) :: before, e
        real(wp) :: work(nwork_kinds), stored(nwork_kinds), nodal(nnodal_sums), gain

        before = start_terms()
        ! gravity gives 2 J, a face 0.5 J; the stored energy grows by 0.25 J, 0.5 J is
        ! dissipated plastically, 0.125 J damped, 0.25 J by friction, 0.125 J stopped,
        ! 0.0625 J absorbed by a face, 0.03125 J taken by a rigid body's constraint, 0.25 J
        ! lost in the transfers: the rest is kinetic
        work = [0.25_wp, 0.5_wp, 0.0_wp]
        stored = before%stored + [0.25_wp, 0.0_wp, 0.0_wp]
        nodal = [0.125_wp, 0.25_wp, 0.125_wp, 0.5_wp, 0.0625_wp, 0.03125_wp]
        gain = 2.0_wp + 0.5_wp - 0.25_wp - 0.5_wp - 0.125_wp - 0.25_wp - 0.125_wp - 0.0625_wp &
            - 0.03125_wp - 0.25_wp
        e = step_energies(before, step_sums(before%kinetic + gain, -2.0_wp, 0.0_wp, work, &
            stored, nodal, [before%kinetic, before%kinetic + gain + 0.25_wp], 0.0_wp), &
            grid_velocities=.true.)
        call check(suite, energy_residual(e) == energy_residual(before), &
            "an exact step adds nothing to the residual")
        call check(suite, energy_total(e) == energy_total(before), "and keeps the total")
        e = step_energies(before, step_sums(before%kinetic + gain + 0.0625_wp, -2.0_wp, &
            0.0_wp, work, stored, nodal, [before%kinetic, before%kinetic + gain + 0.25_wp], &
            0.0_wp), grid_velocities=.true.)
        call check(suite, energy_residual(e) == energy_residual(before), &
            "APIC, PIC: kinetic energy G2P creates is booked as a negative transfer loss")
        e = step_energies(before, step_sums(before%kinetic + gain + 0.0625_wp, -2.0_wp, &
            0.0_wp, work, stored, nodal, [0.0_wp, 0.0_wp], 0.0_wp), grid_velocities=.false.)
        ! the 0.0625 J G2P created and the 0.25 J the nodes lost are nobody's under FLIP
        call check(suite, energy_residual(e) == energy_residual(before) + 0.0625_wp - 0.25_wp, &
            "FLIP: kinetic energy no term explains is residual")
    end subroutine test_closed_step

    !> The checkpoint record gives the terms back; the guard's scale.
    subroutine test_record_and_scale()
        type(energies_type) :: e, back
        real(wp) :: r(nenergy_record)

        e = start_terms()
        e%strain = 1.5_wp
        e%viscous = 0.0625_wp
        e%loads = 0.375_wp
        r = energy_record(e)
        back = energies_from_record(r)
        call check(suite, all(energy_record(back) == r), "record: every term comes back")
        call check(suite, energy_total(e) == 8.0_wp - 2.0_wp + 0.5_wp + 0.0625_wp + &
            0.4375_wp + 0.25_wp + 0.5_wp + 0.125_wp + 0.25_wp - 0.375_wp, &
            "total: kinetic + elastic + potential + dissipated - loads")
        call check(suite, energy_residual(e) == energy_total(e) - 8.0_wp, &
            "residual: total - initial")
        call check(suite, energy_scale(e, 1.0_wp) == 10.0_wp, "scale: initial + supplied")
        call check(suite, energy_scale(e, 64.0_wp) == 64.0_wp, "scale: at least the floor")
    end subroutine test_record_and_scale

end program test_mpm_energy
