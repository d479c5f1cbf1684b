!> Compressible Newtonian fluid: sigma = -p I + 2 mu dev(D), pressure from a bulk modulus.
!>
!> The pressure is carried in the stress (tension positive, p = -tr(sigma)/3) and updated in
!> rate form, p_{n+1} = p_n - K tr(d eps); the viscous stress is recomputed every step from the
!> rate of deformation D = d eps / dt. No state variables.
!>
!> Objectivity needs no Jaumann term: the viscous part depends only on the current D, which is
!> itself objective, and keeps no history to rotate; the pressure part -p I is isotropic, so a
!> rotation leaves it unchanged (Omega (p I) - (p I) Omega = 0), and the trace of the stress,
!> from which p_n is read, is invariant under rotation. The viscous part of the previous step
!> is dropped because it is deviatoric and p_n is read from the trace only.
module mpm_material_newtonian
    use mpm_kinds, only: wp
    use mpm_material, only: material_type, work_viscous
    use mpm_case, only: material_spec_type
    implicit none
    private
    public :: newtonian_material_type, new_newtonian_material

    !> Newtonian fluid with a linear pressure-volume law.
    type, extends(material_type) :: newtonian_material_type
        real(wp) :: viscosity = 0.0_wp
            !! dynamic viscosity mu [Pa s]
        real(wp) :: bulk_modulus = 0.0_wp
            !! bulk modulus K [Pa]
    contains
        procedure :: update_stress => newtonian_update_stress
            !! pressure in rate form plus the viscous stress of the step's strain rate
        procedure :: work_kind => newtonian_work_kind
            !! viscous: the work beyond the stored compression energy is dissipated
        procedure :: elastic_energy_block => newtonian_elastic_energy_block
            !! p^2 / (2 K)
    end type newtonian_material_type

contains

    !> Construct a Newtonian fluid from its case specification (mu, K, rho).
    pure subroutine new_newtonian_material(mat, spec)
        type(newtonian_material_type), intent(out) :: mat
            !! the material
        type(material_spec_type), intent(in) :: spec
            !! case specification
        mat%name = spec%name
        mat%density = spec%density
        mat%viscosity = spec%viscosity
        mat%bulk_modulus = spec%bulk_modulus
    end subroutine new_newtonian_material

    !> The work of the viscous stresses is dissipated.
    pure integer function newtonian_work_kind(self)
        class(newtonian_material_type), intent(in) :: self
            !! the material
        newtonian_work_kind = work_viscous
    end function newtonian_work_kind

    !> Stored (compression) energy per unit volume, p^2 / (2 K), p = -tr(sigma)/3: the
    !> pressure is elastic, the deviatoric stress viscous.
    pure subroutine newtonian_elastic_energy_block(self, n, stress, state, density)
        class(newtonian_material_type), intent(in) :: self
            !! the material
        integer, intent(in) :: n
            !! particles in the block
        real(wp), intent(in) :: stress(:, :)
            !! Cauchy stresses [Pa]
        real(wp), intent(in) :: state(:, :)
            !! unused
        real(wp), intent(out) :: density(:)
            !! stored energy per unit volume [J/m3]

        integer :: j
        real(wp) :: pressure

        do j = 1, n
            pressure = -(stress(1, j) + stress(2, j) + stress(3, j))/3.0_wp
            density(j) = pressure*pressure/(2.0_wp*self%bulk_modulus)
        end do
    end subroutine newtonian_elastic_energy_block

    !> sigma_{n+1} = -p_{n+1} I + 2 mu dev(D), p_{n+1} = -tr(sigma_n)/3 - K tr(d eps),
    !> D = d eps / dt. Plane strain (4 components): D_zz = 0, so
    !> sigma_zz = -p + 2 mu (0 - tr(D)/3). With dt <= 0 only the pressure is updated.
    pure subroutine newtonian_update_stress(self, stress, dstrain, omega, dt, state)
        class(newtonian_material_type), intent(in) :: self
            !! the material
        real(wp), intent(inout) :: stress(:)
            !! Cauchy stress, 4 (2D) or 6 (3D) components, tension positive [Pa]
        real(wp), intent(in) :: dstrain(:)
            !! strain increment D dt, tensor components [-]
        real(wp), intent(in) :: omega(3)
            !! spin increment (unused: see the module notes on objectivity) [-]
        real(wp), intent(in) :: dt
            !! time step [s]
        real(wp), intent(inout) :: state(:)
            !! unused (no state variables)

        real(wp) :: pressure, dvol, de(size(dstrain))

        de = dstrain
        if (size(de) == 4) de(3) = 0.0_wp
        dvol = de(1) + de(2) + de(3)
        pressure = -(stress(1) + stress(2) + stress(3))/3.0_wp - self%bulk_modulus*dvol
        if (dt > 0.0_wp) then
            de(1:3) = de(1:3) - dvol/3.0_wp
            stress = (2.0_wp*self%viscosity/dt)*de
        else
            stress = 0.0_wp
        end if
        stress(1:3) = stress(1:3) - pressure
    end subroutine newtonian_update_stress

end module mpm_material_newtonian
